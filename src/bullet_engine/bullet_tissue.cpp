#include "deformation_enrichment/bullet_engine/bullet_tissue.hpp"

// Bullet's inline code trips GCC's -Wmaybe-uninitialized (btReducedVector, btAlignedObjectArray); the
// diagnostic is emitted after inlining, where -isystem does not silence it.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btDeformableNeoHookeanForce.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <btBulletDynamicsCommon.h>
#pragma GCC diagnostic pop

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/surface_projection.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace deformation_enrichment::bullet_engine {

namespace {

// The contact iterations stop when the largest squared velocity correction falls below this (Bullet units^2).
// Bullet's examples use 1e-3, meant for metre-sized bodies at metres per second; at our speeds the first
// iteration is already below it and face contacts stay unresolved (the body then creeps through the tool).
constexpr double kContactResidual = 1e-12;
// Contact margin of the tissue (m): Bullet's default, 0.25 in its units, would inflate the tool by a quarter
// of a metre. A hundredth of a millimetre keeps contacts alive between steps without a visible gap.
constexpr double kContactMargin = 1e-5;
constexpr double kToolFriction = 1.0;  // static friction: the tissue moves with the tool, as an instrument grips

// Contacts are Lagrange multipliers, solved with the damping by Bullet's conjugate residual, which stops when
// the preconditioned residual's norm (Bullet units, about one tool radius and kilograms) falls below this.
// Bullet's 1e-8 settles a 2 mm press at the slab's corner to 1e-8 m/s at 14 ms a step; 1e-3 to 5e-5 m/s at
// 3.5 ms, its resting nodes within 2e-5 m of the 1e-8 solve's; 1e-2 leaves 1.4e-4 m/s.
constexpr double kCrTolerance = 1e-3;

// m_cr is a protected member of Bullet's solver, meant to be tuned by a derived one.
class BulletSolver : public btDeformableBodySolver {
public:
  BulletSolver() { m_cr.m_tolerance = kCrTolerance; }
};

void requirePositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw InvalidInputError(std::string("BulletTissue: ") + name + " must be positive and finite, got " + std::to_string(value));
}

void validateMaterial(double young, double poisson, double density) {
  requirePositive(young, "young");
  if (!(poisson > 0.0 && poisson < 0.5))
    throw InvalidInputError("BulletTissue: poisson must lie in (0, 0.5), got " + std::to_string(poisson));
  requirePositive(density, "density");
}

void validateOptions(const BulletTissueOptions& o) {
  validateMaterial(o.young, o.poisson, o.density);
  requirePositive(o.damping, "damping");
  requirePositive(o.timeStep, "timeStep");
  requirePositive(o.toolRadius, "toolRadius");
  requirePositive(o.toolSpeed, "toolSpeed");
  if (!(o.massDamping >= 0.0) || !(o.massDamping * o.timeStep < 1.0))
    throw InvalidInputError("BulletTissue: massDamping must lie in [0, 1 / timeStep), got " + std::to_string(o.massDamping));
}

// Bullet's Neo-Hookean energy is the Stable Neo-Hookean of [Smith18] with its log term, whose tangent at rest is
// linear elasticity of (3/4 mu', lambda' - 5/8 mu'). So mu' = 4/3 mu, lambda' = lambda + 5/6 mu give the linear
// elasticity of the scene's (E, nu) at rest, as the package's own SNH solver does [Smith18 §3.4].
// The (E, nu) -> Lame conversion is written out here rather than taken from elasticity::lameFromYoungPoisson:
// that lives in the simulation layer, above the geometry layer this one builds on.
struct BulletLame {
  double mu = 0.0, lambda = 0.0;        // physical, for the damping stress
  double muSnh = 0.0, lambdaSnh = 0.0;  // Bullet's parameters
};

BulletLame bulletLame(double young, double poisson) {
  BulletLame l;
  l.mu = young / (2.0 * (1.0 + poisson));
  l.lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
  l.muSnh = 4.0 / 3.0 * l.mu;
  l.lambdaSnh = l.lambda + 5.0 / 6.0 * l.mu;
  return l;
}

// Where the segment a -> b enters the box [lo, hi], as a parameter in [0, 1] (1 when it never does, 0 when a
// is inside).
double entryParameter(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double enter = 0.0, leave = 1.0;
  const Eigen::Vector3d d = b - a;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < lo[k] || a[k] > hi[k]) return 1.0;
      continue;
    }
    double t0 = (lo[k] - a[k]) / d[k], t1 = (hi[k] - a[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return enter <= leave ? enter : 1.0;
}

}  // namespace

double stableTimeStep(const mesh::TetMesh& rest, double young, double poisson, double density) {
  validateMaterial(young, poisson, density);
  mesh::validate(rest);
  double thinnest = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < rest.numTets(); ++t) {
    double largestFace = 0.0;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d a = rest.vertices.col(rest.tets((k + 1) % 4, t)), b = rest.vertices.col(rest.tets((k + 2) % 4, t)),
                            c = rest.vertices.col(rest.tets((k + 3) % 4, t));
      largestFace = std::max(largestFace, 0.5 * (b - a).cross(c - a).norm());
    }
    thinnest = std::min(thinnest, 3.0 * mesh::signedVolume(rest, t) / largestFace);
  }
  const BulletLame lame = bulletLame(young, poisson);
  return 1.5 * thinnest / std::sqrt((lame.lambda + 2.0 * lame.mu) / density);
}

struct BulletTissue::Impl {
  mesh::TetMesh rest;
  BulletTissueOptions options;
  Eigen::Vector3d park = Eigen::Vector3d::Zero();
  std::unique_ptr<mesh::SurfaceProjector> boundary;  // the rest body's surface: where a parked tool enters
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // commanded tool centre (m)
  double diagonal = 0.0;                              // of the rest bounding box (m)
  // Bullet length units per metre, a power of two (so scaling is exact): the tool radius is about one unit.
  // Bullet's absolute constants (velocity clamps, margins, distance-field cells, solver thresholds) are tuned
  // for bodies of metres; in these units a tool of millimetres is one.
  double scale = 1.0;
  btAlignedObjectArray<btVector3> previous;  // node positions before the last step (Bullet units)
  long divergences = 0;
  // At rest with the tool parked, untouched since construction or reset: a Bullet step would change nothing
  // (no gravity, no contact) but still cost its full linear solve (2.5 ms on the slab, on round-off noise),
  // so it is skipped.
  bool idle = true;

  // Construction order; destroyed in reverse, after ~Impl has taken the bodies out of the world.
  std::unique_ptr<btSoftBodyRigidBodyCollisionConfiguration> configuration;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<BulletSolver> bodySolver;
  std::unique_ptr<btDeformableMultiBodyConstraintSolver> constraintSolver;
  std::unique_ptr<btDeformableMultiBodyDynamicsWorld> world;
  std::unique_ptr<btDeformableNeoHookeanForce> elasticity;
  std::unique_ptr<btSoftBody> body;
  std::unique_ptr<btSphereShape> toolShape;
  std::unique_ptr<btDefaultMotionState> toolMotion;
  std::unique_ptr<btRigidBody> tool;

  Impl(const mesh::TetMesh& mesh, const std::vector<int>& fixed, const BulletTissueOptions& o);
  ~Impl() {
    world->removeRigidBody(tool.get());
    world->removeSoftBody(body.get());
  }
  void makeWorld();
  void makeBody(const std::vector<int>& fixed);
  void makeTool();
  void placeTool(const Eigen::Vector3d& centre, bool jump);
  Eigen::Vector3d toolCentre() const;
  void advanceTool();
  bool diverged() const;
  void dampMass();
  void reset();
  btVector3 toBullet(const Eigen::Vector3d& v) const { return btVector3(v.x(), v.y(), v.z()) * scale; }
  Eigen::Vector3d fromBullet(const btVector3& v) const { return Eigen::Vector3d(v.x(), v.y(), v.z()) / scale; }
};

BulletTissue::Impl::Impl(const mesh::TetMesh& mesh, const std::vector<int>& fixed, const BulletTissueOptions& o)
    : rest(mesh), options(o) {
  validateOptions(o);
  mesh::validate(rest);
  for (int v : fixed)
    if (v < 0 || v >= rest.numVertices())
      throw InvalidInputError("BulletTissue: fixed vertex " + std::to_string(v) + " is not among the mesh's " +
                              std::to_string(rest.numVertices()) + " vertices");
  const Eigen::Vector3d lo = rest.vertices.rowwise().minCoeff(), hi = rest.vertices.rowwise().maxCoeff();
  diagonal = (hi - lo).norm();
  scale = std::exp2(std::round(std::log2(1.0 / o.toolRadius)));
  // Above the body by more than its size: no contact.
  park = 0.5 * (lo + hi) + (diagonal + 4.0 * o.toolRadius) * Eigen::Vector3d::UnitZ();
  target = park;
  boundary = std::make_unique<mesh::SurfaceProjector>(mesh::extractSurface(rest).surface);
  makeWorld();
  makeBody(fixed);
  makeTool();
}

void BulletTissue::Impl::makeWorld() {
  configuration = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  dispatcher = std::make_unique<btCollisionDispatcher>(configuration.get());
  broadphase = std::make_unique<btDbvtBroadphase>();
  bodySolver = std::make_unique<BulletSolver>();
  constraintSolver = std::make_unique<btDeformableMultiBodyConstraintSolver>();
  constraintSolver->setDeformableSolver(bodySolver.get());
  world = std::make_unique<btDeformableMultiBodyDynamicsWorld>(dispatcher.get(), broadphase.get(), constraintSolver.get(),
                                                               configuration.get(), bodySolver.get());
  world->setGravity(btVector3(0, 0, 0));
  world->getWorldInfo().m_gravity.setZero();
  // The sphere's distance field is sampled on this grid and interpolated trilinearly.
  world->getWorldInfo().m_sparsesdf.setDefaultVoxelsz(scale * options.toolRadius / 10.0);
  world->getWorldInfo().m_sparsesdf.Reset();
  // Elastic forces explicit, damping implicit, contacts by Lagrange multipliers. The implicit elastic solve
  // (setImplicit(true)) let the tissue creep through the tool by millimetres a second in contact and costs 9x;
  // explicit elastic forces hold below about 1.5 pressure-wave crossings of the thinnest tet a step
  // (stableTimeStep). Contacts by velocity projection (setUseProjection(true)) cost half as much in the middle
  // of the slab but blow up within ten steps wherever the tool touches an edge or a corner of the surface.
  world->setImplicit(false);
  world->setLineSearch(false);
  world->setUseProjection(false);
  btContactSolverInfo& info = world->getSolverInfo();
  info.m_deformable_erp = 0.3;  // as Bullet's DeformableDemo examples
  info.m_deformable_maxErrorReduction = btScalar(200);
  info.m_leastSquaresResidualThreshold = kContactResidual;
  info.m_splitImpulse = true;
  info.m_numIterations = 100;
}

void BulletTissue::Impl::makeBody(const std::vector<int>& fixed) {
  const Eigen::VectorXd volumes = mesh::lumpedVertexVolumes(rest);
  btAlignedObjectArray<btVector3> x;
  btAlignedObjectArray<btScalar> m;
  for (Eigen::Index v = 0; v < rest.numVertices(); ++v) {
    x.push_back(toBullet(rest.vertices.col(v)));
    m.push_back(options.density * volumes[v]);
  }
  for (int v : fixed) m[v] = 0.0;  // Bullet holds zero-mass nodes where they are
  previous = x;
  body = std::make_unique<btSoftBody>(&world->getWorldInfo(), x.size(), &x[0], &m[0]);
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index t = 0; t < rest.numTets(); ++t) {
    const Eigen::Vector4i n = rest.tets.col(t);
    body->appendTetra(n[0], n[1], n[2], n[3]);
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) edges.insert({std::min(n[a], n[b]), std::max(n[a], n[b])});
  }
  // Links carry no force here (no mass-spring force is added), but Bullet builds its node tree for contacts
  // by pairing linked nodes: without links that loop never ends.
  for (const auto& [a, b] : edges) body->appendLink(a, b, nullptr, /*bcheckexist=*/false);
  body->initializeDmInverse();
  body->m_tetraScratches.resize(body->m_tetras.size());
  body->m_tetraScratchesTn.resize(body->m_tetras.size());
  btSoftBodyHelpers::generateBoundaryFaces(body.get());
  body->getCollisionShape()->setMargin(scale * kContactMargin);
  body->m_cfg.kKHR = 1;  // contact hardness against kinematic objects
  body->m_cfg.kCHR = 1;
  body->m_cfg.kDF = 1;   // friction = kDF x the tool's friction
  // Face contacts, which cover the nodes too (a face's point nearest the tool may be a corner): the tool may
  // press between nodes (1 cm apart on the slab, wider than the tool), where node contacts (SDF_RDN) alone
  // let it pass through the surface.
  body->m_cfg.collisions = btSoftBody::fCollision::SDF_RD | btSoftBody::fCollision::SDF_RDF;
  body->m_sleepingThreshold = 0;
  body->setActivationState(DISABLE_DEACTIVATION);
  world->addSoftBody(body.get());

  // Stress in Bullet's units (kg, Bullet length, s) is the stress in Pa over the scale.
  const BulletLame lame = bulletLame(options.young / scale, options.poisson);
  elasticity = std::make_unique<btDeformableNeoHookeanForce>(lame.muSnh, lame.lambdaSnh);
  // Damping stress = damping x (linear elastic stress of the strain rate), with the physical moduli.
  elasticity->m_mu_damp = options.damping * lame.mu;
  elasticity->m_lambda_damp = options.damping * lame.lambda;
  world->addForce(body.get(), elasticity.get());
}

void BulletTissue::Impl::makeTool() {
  toolShape = std::make_unique<btSphereShape>(scale * options.toolRadius);
  btTransform pose;
  pose.setIdentity();
  pose.setOrigin(toBullet(park));
  toolMotion = std::make_unique<btDefaultMotionState>(pose);
  btRigidBody::btRigidBodyConstructionInfo info(0.0, toolMotion.get(), toolShape.get(), btVector3(0, 0, 0));
  tool = std::make_unique<btRigidBody>(info);
  tool->setCollisionFlags(tool->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  tool->setActivationState(DISABLE_DEACTIVATION);
  tool->setFriction(kToolFriction);
  world->addRigidBody(tool.get());
}

Eigen::Vector3d BulletTissue::Impl::toolCentre() const {
  btTransform pose;
  toolMotion->getWorldTransform(pose);
  return fromBullet(pose.getOrigin());
}

// A kinematic body's velocity is what Bullet derives from its motion state's change over a step. A move sets
// the motion state only; a jump sets every transform Bullet keeps, so the derived velocity is zero.
void BulletTissue::Impl::placeTool(const Eigen::Vector3d& centre, bool jump) {
  btTransform pose;
  pose.setIdentity();
  pose.setOrigin(toBullet(centre));
  toolMotion->setWorldTransform(pose);
  if (jump) {
    tool->setWorldTransform(pose);
    tool->setInterpolationWorldTransform(pose);
    tool->setLinearVelocity(btVector3(0, 0, 0));
    tool->setInterpolationLinearVelocity(btVector3(0, 0, 0));
  }
}

// One step of the tool towards its target: a jump over the part of the way that stays clear of the body (its
// current bounding box grown by two radii), then at most toolSpeed x timeStep. A tool entering the tissue at a
// command's full speed (metres a step) makes the contact solve explode.
void BulletTissue::Impl::advanceTool() {
  const Eigen::Vector3d from = toolCentre();
  if (from == target) return;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(BT_LARGE_FLOAT), hi = -lo;
  for (int i = 0; i < body->m_nodes.size(); ++i) {
    const Eigen::Vector3d x = fromBullet(body->m_nodes[i].m_x);
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const Eigen::Vector3d grow = Eigen::Vector3d::Constant(2.0 * options.toolRadius);
  const double clear = entryParameter(from, target, lo - grow, hi + grow);
  if (clear > 0.0) {
    placeTool(from + clear * (target - from), /*jump=*/true);
    return;
  }
  const Eigen::Vector3d way = target - from;
  const double reach = options.toolSpeed * options.timeStep;
  placeTool(way.norm() <= reach ? target : Eigen::Vector3d(from + reach * way.normalized()), /*jump=*/false);
}

// Mass-proportional (Rayleigh alpha) damping, explicit: every node's velocity loses massDamping x timeStep of
// itself a step. Bullet's deformable solver has no such term (btSoftBody's damping coefficient is not read
// by it), and the stiffness-proportional one alone leaves the slow modes of a large organ ringing.
void BulletTissue::Impl::dampMass() {
  const double keep = 1.0 - options.massDamping * options.timeStep;
  for (int i = 0; i < body->m_nodes.size(); ++i) body->m_nodes[i].m_v *= keep;
}

// Bullet clamps node velocities (to 1000 units a step) rather than producing NaN, so a blown-up state is
// mostly finite: a node farther from rest than the body is large has left any elastic response.
bool BulletTissue::Impl::diverged() const {
  for (int i = 0; i < body->m_nodes.size(); ++i) {
    const Eigen::Vector3d x = fromBullet(body->m_nodes[i].m_x);
    if (!x.allFinite() || (x - rest.vertices.col(i)).norm() > diagonal) return true;
  }
  return false;
}

void BulletTissue::Impl::reset() {
  for (int i = 0; i < body->m_nodes.size(); ++i) {
    btSoftBody::Node& n = body->m_nodes[i];
    n.m_x = n.m_q = previous[i] = toBullet(rest.vertices.col(i));
    n.m_v.setZero();
    n.m_vn.setZero();
    n.m_f.setZero();
    n.m_splitv.setZero();
  }
  body->updateBounds();
  target = park;
  placeTool(park, /*jump=*/true);
  idle = true;
}

BulletTissue::BulletTissue(const mesh::TetMesh& rest, const std::vector<int>& fixedVertices, const BulletTissueOptions& options)
    : impl_(std::make_unique<Impl>(rest, fixedVertices, options)) {}

BulletTissue::~BulletTissue() = default;

void BulletTissue::setToolCentre(const Eigen::Vector3d& centre) {
  if (!centre.allFinite()) throw InvalidInputError("BulletTissue: the tool centre is not finite");
  if (centre != impl_->park && impl_->toolCentre() == impl_->park) {
    // A parked tool enters at once, two radii out along the surface normal nearest the command, and moves in
    // from there: the way from the park position above the body to a contact beside or under an organ crosses
    // the tissue and would drag it along (the CGAL liver: states 6 cm RMS from rest before contact).
    const mesh::SurfacePoint nearest = impl_->boundary->project(centre);
    impl_->placeTool(nearest.point + 2.0 * impl_->options.toolRadius * nearest.normal, /*jump=*/true);
  }
  impl_->target = centre;
  impl_->idle = impl_->idle && centre == impl_->park;
}

void BulletTissue::parkTool() {
  impl_->target = impl_->park;
  impl_->placeTool(impl_->park, /*jump=*/true);
}

Eigen::Vector3d BulletTissue::toolCentre() const { return impl_->toolCentre(); }

bool BulletTissue::step(int n) {
  btSoftBody& b = *impl_->body;
  if (impl_->idle) return true;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < b.m_nodes.size(); ++k) impl_->previous[k] = b.m_nodes[k].m_x;
    impl_->advanceTool();
    // maxSubSteps 0: exactly one internal step of timeStep (Bullet's variable-step mode).
    impl_->world->stepSimulation(impl_->options.timeStep, 0);
    impl_->dampMass();
    if (impl_->diverged()) {
      ++impl_->divergences;
      impl_->reset();
      return false;
    }
  }
  return true;
}

Eigen::Matrix3Xd BulletTissue::positions() const {
  const btSoftBody& b = *impl_->body;
  Eigen::Matrix3Xd x(3, b.m_nodes.size());
  for (int i = 0; i < b.m_nodes.size(); ++i) x.col(i) = impl_->fromBullet(b.m_nodes[i].m_x);
  return x;
}

// From the positions, not Bullet's node velocities: in contact those carry a velocity that the split impulse
// (position correction) cancels every step, so a node at rest can report centimetres a second.
double BulletTissue::largestSpeed() const {
  const btSoftBody& b = *impl_->body;
  double farthest = 0.0;
  for (int i = 0; i < b.m_nodes.size(); ++i) farthest = std::max(farthest, double((b.m_nodes[i].m_x - impl_->previous[i]).length()));
  return farthest / impl_->scale / impl_->options.timeStep;
}

void BulletTissue::reset() { impl_->reset(); }

long BulletTissue::divergences() const { return impl_->divergences; }
const mesh::TetMesh& BulletTissue::rest() const { return impl_->rest; }
const BulletTissueOptions& BulletTissue::options() const { return impl_->options; }

}  // namespace deformation_enrichment::bullet_engine
