#pragma once
// CalculiX input deck of a tet body under Dirichlet conditions, for an independent check of our SNH solver
// with a compressible neo-Hookean solid ([Dhondt04]; CalculiX 2.20 manual, *HYPERELASTIC). CalculiX (ccx,
// GPL) is run as a separate program (calculix_run.hpp), never linked.
//
// Material: U = C10 (I1_bar - 3) + (J - 1)^2 / D1 with I1_bar = J^(-2/3) I1. Its tangent at rest is linear
// elasticity with shear modulus 2 C10 and bulk modulus 2 / D1, so C10 = mu / 2 and D1 = 2 / kappa where
// mu and kappa = lambda + 2/3 mu are the physical moduli of (E, nu). Our SNH (both variants) is
// re-parameterised (mu', lambda') so that its tangent at rest equals linear elasticity of the same Lamé
// (mu, lambda) = lameFromYoungPoisson(E, nu) ([Smith18 §3.4]); both models thus agree to first order.
//
// Mesh: C3D4 wants nodes 1-2-3 counter-clockwise seen from node 4, i.e. det[x2-x1, x3-x1, x4-x1] > 0,
// which is the TetMesh convention (det[x1-x0, x2-x0, x3-x0] > 0), so tets are written in their own order
// (ccx rejects the other orientation: "nonpositive jacobian").
#include <Eigen/Core>
#include <ostream>
#include <vector>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::elasticity {

/// An isotropic material given by Young's modulus (Pa) and Poisson ratio, 0 < nu < 1/2.
struct IsotropicMaterial {
  double youngModulus = 0.0;
  double poissonRatio = 0.0;
};

/// CalculiX's NEO HOOKE constants of a material: C10 = mu / 2, D1 = 2 / kappa.
struct NeoHookeConstants {
  double c10;
  double d1;
};
/// Throws InvalidInputError for E <= 0 or nu outside (0, 1/2).
NeoHookeConstants neoHookeConstants(const IsotropicMaterial& material);

/// A body, its materials per tet and its Dirichlet conditions: constrained vertices (all three axes) move
/// to the given positions; a vertex held at its rest position is a fixed support.
struct CalculixModel {
  mesh::TetMesh rest;
  std::vector<IsotropicMaterial> materials;
  Eigen::VectorXi materialId;  ///< per tet, an index into materials (as TetFem)
  DirichletConstraints constraints;
  /// The step is ramped from rest in at least this many equal increments (ccx may cut them further).
  int increments = 4;
  /// ccx's relative force (R_n) and correction (C_n) tolerances; its defaults 0.005 and 0.01 leave
  /// displacement errors around 1e-3, too coarse for a 1 % comparison at small strain.
  double residualTolerance = 1e-8;
};

/// Throws InvalidInputError naming the problem: an invalid mesh, no materials, material ids of the
/// wrong size or range, invalid materials, constraints of the wrong shape, out-of-range or repeated
/// vertices, non-finite positions, increments < 1 or a non-positive tolerance.
void validate(const CalculixModel& model);

/// Writes the deck (validated first): nodes 1..V (NSET=Nall), elements 1..T of type C3D4 in one element
/// set M<k> per used material, *MATERIAL M<k> with *HYPERELASTIC, NEO HOOKE, one *STEP, NLGEOM with
/// *STATIC, the *BOUNDARY displacements and *NODE PRINT of U for Nall. Throws IoError if writing fails.
void writeCalculixDeck(std::ostream& out, const CalculixModel& model);

}  // namespace deformation_enrichment::elasticity
