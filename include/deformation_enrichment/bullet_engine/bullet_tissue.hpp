#pragma once
// A coarse tet volume simulated by Bullet's deformable bodies (btDeformableMultiBodyDynamicsWorld,
// btDeformableNeoHookeanForce: elastic forces explicit, damping implicit) and touched by a kinematic rigid
// sphere with friction: a stand-in for a user's own simulator (as AMBF would be) that the acquisition
// pipeline talks to over ROS. How Bullet is configured, and why, is in the .cpp.
//
// What it leaves out, and why: Bullet has one material per force and no per-element materials, so the whole
// body takes one (E, nu), the scene's bulk; a stiff skin layer of the scene is not represented. There is no
// gravity, as in the scene's own quasi-static solver. Fixed vertices are Bullet nodes of zero mass (held
// where they are). Bullet's headers stay in the .cpp (pimpl): they are compiled double precision
// (BT_USE_DOUBLE_PRECISION), which every includer would have to agree on.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::bullet_engine {

struct BulletTissueOptions {
  double young = 0.0;       ///< Young's modulus (Pa), > 0
  double poisson = 0.0;     ///< Poisson ratio in (0, 0.5)
  double density = 1000.0;  ///< kg/m^3, > 0: lumped node masses
  /// Stiffness-proportional (Rayleigh beta) damping in seconds, > 0: the damping stress is
  /// damping x (linear elastic stress of the strain rate). The slab's slowest mode (shear through its
  /// thickness, omega ~ 150 rad/s) is damped critically at 2 / omega = 0.013 s; 0.01 settles a 3 mm indentation
  /// of the slab in 0.06 s of simulated time (0.005: 0.08 s, 0.02: 0.1 s).
  double damping = 0.01;
  /// Mass-proportional (Rayleigh alpha) damping in 1/s, in [0, 1 / timeStep): a drag on every node's velocity.
  /// Stiffness-proportional damping barely touches the slowest modes: a 3 mm press on the CGAL liver still
  /// moved at 2e-4 m/s after 7 s of simulated time; with 20 it settles below 1e-6 m/s within 1.1 s. On the
  /// slab it changes the settling time by under 1 %.
  double massDamping = 20.0;
  /// Simulated seconds per Bullet step, > 0. Elastic forces are explicit, so the step is bounded by the
  /// mesh (stableTimeStep): on the slab 5e-4 s holds 3 mm indentations and blows up at 5 mm, 2.5e-4 s holds 6 mm.
  double timeStep = 2.5e-4;
  double toolRadius = 0.0;   ///< the tool sphere's radius (m), > 0
  /// Fastest the tool's centre moves towards its commanded position (m/s), > 0. A command is followed at
  /// this speed (so Bullet's contacts see the tool's true velocity; on the slab 3 m/s still settles, a jump
  /// into the tissue blows up); the part of a move that stays clear of the body (from the park position,
  /// say) is a jump.
  double toolSpeed = 0.1;
};

/// A Bullet step that holds on `rest`: 1.5 x the time a pressure wave (speed sqrt((lambda + 2 mu) / density))
/// takes across the thinnest tet (its smallest height). Measured limits, in that unit: the slab blows up at
/// 6 (1e-3 s), holds 3 mm at 3 and 6 mm at 1.5; the pillow holds 6 mm at 1.5; the meniscus (measured with
/// contacts by velocity projection, before the Lagrange multipliers in use) blew up at 4 and held 2 mm at 1.5
/// (3.7e-5 s). Throws InvalidInputError for an invalid mesh or material.
double stableTimeStep(const mesh::TetMesh& rest, double young, double poisson, double density);

class BulletTissue {
public:
  /// Throws InvalidInputError naming the problem for an invalid or empty mesh, fixed vertex ids out of range
  /// or options that are not positive and finite (Poisson ratio outside (0, 0.5)).
  BulletTissue(const mesh::TetMesh& rest, const std::vector<int>& fixedVertices, const BulletTissueOptions& options);
  ~BulletTissue();
  BulletTissue(const BulletTissue&) = delete;
  BulletTissue& operator=(const BulletTissue&) = delete;

  /// Commands the tool sphere's centre (m); the sphere moves there over the next steps (toolSpeed). A parked
  /// tool enters at once two radii out along the rest surface's normal at the point nearest `centre`, so it
  /// does not sweep through the body on its way. Throws InvalidInputError for a non-finite centre.
  void setToolCentre(const Eigen::Vector3d& centre);
  /// Moves the tool far from the body at once (no contact).
  void parkTool();
  /// Where the tool's centre is now (it may still be on its way to the commanded centre).
  Eigen::Vector3d toolCentre() const;

  /// Advances `n` Bullet steps of timeStep each. When Bullet blows up (a node non-finite or farther from
  /// its rest position than the body's bounding-box diagonal) the tissue is reset (reset()), the divergence
  /// counted, and false returned; positions() are then always finite. At rest with the tool parked, untouched
  /// since construction or reset(), nothing can move and no Bullet step is run.
  bool step(int n = 1);
  /// Node positions (3 x N, the rest mesh's order).
  Eigen::Matrix3Xd positions() const;
  /// Largest node speed over the last step (m/s), from the positions.
  double largestSpeed() const;
  /// Positions back to rest, velocities zero, tool parked.
  void reset();
  /// How often step() found Bullet blown up.
  long divergences() const;

  const mesh::TetMesh& rest() const;
  const BulletTissueOptions& options() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deformation_enrichment::bullet_engine
