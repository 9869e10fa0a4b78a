#include "deformation_enrichment/elasticity/calculix_deck.hpp"

#include <cmath>
#include <iomanip>
#include <set>
#include <string>

#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::elasticity {
namespace {

// ccx 2.20 reads each real of a data line from its first 20 characters (Fortran f20.0): 13 significant
// digits fit with sign, point and a three-digit exponent; 17 would be cut off silently.
constexpr int kDigits = 13;

void writeNodes(std::ostream& out, const mesh::TetMesh& rest) {
  out << "*NODE, NSET=Nall\n";
  for (Eigen::Index v = 0; v < rest.numVertices(); ++v)
    out << v + 1 << ", " << rest.vertices(0, v) << ", " << rest.vertices(1, v) << ", " << rest.vertices(2, v) << '\n';
}

// One element set per material (M0, M1, ...), so each gets its own *SOLID SECTION; element numbers stay
// tet index + 1 whatever set a tet is in.
void writeElementsAndMaterials(std::ostream& out, const CalculixModel& model) {
  for (std::size_t k = 0; k < model.materials.size(); ++k) {
    if ((model.materialId.array() != static_cast<int>(k)).all()) continue;  // ccx rejects an empty set
    const std::string name = "M" + std::to_string(k);
    out << "*ELEMENT, TYPE=C3D4, ELSET=" << name << '\n';
    for (Eigen::Index t = 0; t < model.rest.numTets(); ++t) {
      if (model.materialId[t] != static_cast<int>(k)) continue;
      out << t + 1;
      for (int c = 0; c < 4; ++c) out << ", " << model.rest.tets(c, t) + 1;
      out << '\n';
    }
    const NeoHookeConstants nh = neoHookeConstants(model.materials[k]);
    out << "*MATERIAL, NAME=" << name << "\n*HYPERELASTIC, NEO HOOKE\n" << nh.c10 << ", " << nh.d1 << '\n'
        << "*SOLID SECTION, ELSET=" << name << ", MATERIAL=" << name << '\n';
  }
}

// Displacements of the constrained nodes, ramped over the step (ccx's default amplitude of a static step).
void writeBoundary(std::ostream& out, const CalculixModel& model) {
  out << "*BOUNDARY\n";
  const DirichletConstraints& c = model.constraints;
  for (std::size_t k = 0; k < c.vertices.size(); ++k) {
    const int node = c.vertices[k] + 1;
    const Eigen::Vector3d u = c.positions.col(static_cast<Eigen::Index>(k)) - model.rest.vertices.col(c.vertices[k]);
    if (u.isZero(0.0)) {
      out << node << ", 1, 3, 0\n";  // a fixed support
      continue;
    }
    for (int axis = 0; axis < 3; ++axis) out << node << ", " << axis + 1 << ", " << axis + 1 << ", " << u[axis] << '\n';
  }
}

}  // namespace

NeoHookeConstants neoHookeConstants(const IsotropicMaterial& material) {
  const LameParameters lame = lameFromYoungPoisson(material.youngModulus, material.poissonRatio);
  const double bulk = lame.lambda + 2.0 / 3.0 * lame.mu;  // kappa = lambda + 2/3 mu
  return {0.5 * lame.mu, 2.0 / bulk};
}

void validate(const CalculixModel& model) {
  mesh::validate(model.rest);
  if (model.materials.empty()) throw InvalidInputError("CalculiX deck: no materials");
  for (const IsotropicMaterial& material : model.materials) neoHookeConstants(material);  // throws if invalid
  if (model.materialId.size() != model.rest.numTets() ||
      (model.materialId.size() > 0 &&
       (model.materialId.minCoeff() < 0 || model.materialId.maxCoeff() >= static_cast<int>(model.materials.size()))))
    throw InvalidInputError("CalculiX deck: need one material id in [0, " + std::to_string(model.materials.size()) +
                            ") per tet, got " + std::to_string(model.materialId.size()) + " ids for " +
                            std::to_string(model.rest.numTets()) + " tets");
  const DirichletConstraints& c = model.constraints;
  if (c.positions.cols() != static_cast<Eigen::Index>(c.vertices.size()) || !c.positions.allFinite())
    throw InvalidInputError("CalculiX deck: constraints need one finite position per constrained vertex");
  std::set<int> seen;
  for (int v : c.vertices) {
    if (v < 0 || v >= model.rest.numVertices())
      throw InvalidInputError("CalculiX deck: constrained vertex " + std::to_string(v) + " out of range");
    if (!seen.insert(v).second) throw InvalidInputError("CalculiX deck: vertex " + std::to_string(v) + " constrained twice");
  }
  if (model.increments < 1) throw InvalidInputError("CalculiX deck: increments must be at least 1");
  if (!(model.residualTolerance > 0.0) || !std::isfinite(model.residualTolerance))
    throw InvalidInputError("CalculiX deck: the residual tolerance must be finite and positive");
}

void writeCalculixDeck(std::ostream& out, const CalculixModel& model) {
  validate(model);
  const double increment = 1.0 / model.increments;
  out << std::setprecision(kDigits) << "*HEADING\ndeformation_enrichment: tet body under prescribed displacements\n";
  writeNodes(out, model.rest);
  writeElementsAndMaterials(out, model);
  // Initial and largest increment 1/n, so at least n increments; ccx halves them when Newton struggles.
  out << "*STEP, NLGEOM, INC=" << 1000 * model.increments << "\n*STATIC\n"
      << increment << ", 1.0, " << 1e-6 * increment << ", " << increment << '\n'
      << "*CONTROLS, PARAMETERS=FIELD\n" << model.residualTolerance << ", " << model.residualTolerance << '\n';
  writeBoundary(out, model);
  out << "*NODE PRINT, NSET=Nall\nU\n*END STEP\n";
  if (!out) throw IoError("CalculiX deck: writing failed");
}

}  // namespace deformation_enrichment::elasticity
