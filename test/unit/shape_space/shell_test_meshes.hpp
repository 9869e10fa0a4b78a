#pragma once
// Small meshes and perturbations shared by the Discrete Shells tests.
#include <random>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"

namespace deformation_enrichment::shape_space::test {

/// Every output of one evaluation, for tests that compare them all at once.
struct AllOutputs {
  double value = 0.0;
  Eigen::VectorXd gradientDeformed, gradientReference;
  Eigen::SparseMatrix<double> hessianDeformed, hessianMixed, hessianReference;
};

/// All outputs of energy.evaluate in one call (value and gradients only if !withHessians).
inline AllOutputs evaluateAll(const DeformationEnergy& energy, const Eigen::VectorXd& reference,
                              const Eigen::VectorXd& deformed, bool withHessians = true) {
  AllOutputs r;
  EnergyOutputs outputs;
  outputs.value = &r.value;
  outputs.gradientDeformed = &r.gradientDeformed;
  outputs.gradientReference = &r.gradientReference;
  if (withHessians) {
    outputs.hessianDeformed = &r.hessianDeformed;
    outputs.hessianMixed = &r.hessianMixed;
    outputs.hessianReference = &r.hessianReference;
  }
  energy.evaluate(reference, deformed, outputs);
  return r;
}

struct FlatMesh {
  Eigen::Matrix3Xi triangles;
  Eigen::VectorXd vertices;  // 3V, xyz per vertex
};

/// n x n vertex grid over [0,1]^2 with a smooth bump plus noise in z (open: has boundary edges).
inline FlatMesh bumpyGrid(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.02, 0.02);
  FlatMesh m;
  m.vertices.resize(3 * n * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = i / double(n - 1), y = j / double(n - 1);
      const int v = j * n + i;
      m.vertices.segment<3>(3 * v) << x + noise(rng), y + noise(rng), 0.8 * x * (1 - x) * y * (1 - y) + noise(rng);
    }
  }
  m.triangles.resize(3, 2 * (n - 1) * (n - 1));
  int t = 0;
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      m.triangles.col(t++) << a, b, d;
      m.triangles.col(t++) << a, d, c;
    }
  }
  return m;
}

/// Closed octahedron (every edge has two triangles), slightly irregular, outward winding.
inline FlatMesh octahedron() {
  FlatMesh m;
  m.vertices.resize(18);
  m.vertices << 1.0, 0.05, 0.0, -1.1, 0.0, 0.02, 0.0, 0.9, 0.0, 0.03, -1.0, 0.0, 0.0, 0.0, 1.2, 0.0, 0.04, -0.95;
  m.triangles.resize(3, 8);
  m.triangles << 0, 2, 1, 3, 2, 0, 3, 1,  //
      2, 1, 3, 0, 0, 3, 1, 2,             //
      4, 4, 4, 4, 5, 5, 5, 5;
  return m;
}

/// Forwards only numVertices and evaluate, so checkShape, pathSegments, onTriangles, weightedReferences,
/// referenceData and pathEnergy run the interface's defaults.
class ForwardingEnergy final : public DeformationEnergy {
public:
  explicit ForwardingEnergy(const DiscreteShells& inner) : inner_(inner) {}
  Eigen::Index numVertices() const override { return inner_.numVertices(); }
  void evaluate(const Eigen::VectorXd& r, const Eigen::VectorXd& d, const EnergyOutputs& outputs) const override {
    inner_.evaluate(r, d, outputs);
  }

private:
  const DiscreteShells& inner_;
};

/// vertices + uniform noise of the given amplitude per coordinate.
inline Eigen::VectorXd perturbed(const Eigen::VectorXd& vertices, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  Eigen::VectorXd out = vertices;
  for (Eigen::Index i = 0; i < out.size(); ++i) out[i] += noise(rng);
  return out;
}

}  // namespace deformation_enrichment::shape_space::test
