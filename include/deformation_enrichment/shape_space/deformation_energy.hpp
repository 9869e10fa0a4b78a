#pragma once
// Deformation energy W[x_bar, x] between a reference (undeformed) shape x_bar and a deformed shape x over
// one fixed topology ([Brandt16 §3]: the dissimilarity measure of shape space). Shapes are flat vectors of
// size 3V, xyz per vertex: (x_0, y_0, z_0, x_1, ...). The energy is not symmetric in its arguments.
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace deformation_enrichment::shape_space {

/// Where DeformationEnergy::evaluate writes each output; null members are not computed.
struct EnergyOutputs {
  double* value = nullptr;
  Eigen::VectorXd* gradientDeformed = nullptr;
  Eigen::VectorXd* gradientReference = nullptr;
  Eigen::SparseMatrix<double>* hessianDeformed = nullptr;
  Eigen::SparseMatrix<double>* hessianMixed = nullptr;
  Eigen::SparseMatrix<double>* hessianReference = nullptr;
};

/// sum_i w_i W[x_i, y] with fixed references x_i as a function of y alone: the objective of an eq. 10
/// average, prepared once and evaluated many times.
class WeightedReferenceEnergy {
public:
  virtual ~WeightedReferenceEnergy() = default;
  /// The value; with gradient, its derivative in y. Throws InvalidInputError for a wrongly sized,
  /// non-finite or degenerate y.
  virtual double evaluate(const Eigen::VectorXd& deformed, Eigen::VectorXd* gradient) const = 0;
  /// The Hessian in y (both triangles stored); same errors.
  virtual Eigen::SparseMatrix<double> hessian(const Eigen::VectorXd& deformed) const = 0;
};

/// What an energy computes from a reference shape alone, kept for every weightedReferences call that uses the
/// shape as a reference (a smoothing step's shapes serve 3-4 averages each). Opaque to callers.
class ReferenceData {
public:
  virtual ~ReferenceData() = default;
};

class DeformationEnergy {
public:
  virtual ~DeformationEnergy() = default;

  /// Number of vertices V of the fixed topology; every shape argument has size 3V.
  virtual Eigen::Index numVertices() const = 0;

  /// Throws InvalidInputError naming the problem if `shape` cannot be an argument: wrong size or a
  /// non-finite entry (the default), plus the implementation's own conditions (e.g. degenerate triangles).
  virtual void checkShape(const Eigen::VectorXd& shape) const;

  /// Several outputs at once, e.g. evaluate(xBar, x, {&value, &gradient, nullptr, &hessian}); an
  /// implementation shares one pass between them.
  virtual void evaluate(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed,
                        const EnergyOutputs& outputs) const = 0;

  // One output each, computed by one evaluate call.

  /// W[reference, deformed].
  double value(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;

  /// dW/dx, size 3V (derivative with respect to the deformed shape).
  Eigen::VectorXd gradientDeformed(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;

  /// dW/dx_bar, size 3V (derivative with respect to the reference shape).
  Eigen::VectorXd gradientReference(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;

  /// d^2W/dx^2, 3V x 3V, symmetric (both triangles stored).
  Eigen::SparseMatrix<double> hessianDeformed(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;

  /// d^2W/(dx_bar dx), 3V x 3V: entry (i, j) = d^2W / (d x_bar_i d x_j), i.e. rows index the reference
  /// and columns the deformed shape. Its transpose is d^2W/(dx dx_bar).
  Eigen::SparseMatrix<double> hessianMixed(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;

  /// d^2W/dx_bar^2, 3V x 3V, symmetric (both triangles stored).
  Eigen::SparseMatrix<double> hessianReference(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;

  /// The same energy (same parameters) over another triangle topology of numVertices vertices, e.g. a ghost
  /// mesh (ghost_mesh.hpp). The default throws InvalidInputError: not every energy has one.
  virtual std::unique_ptr<DeformationEnergy> onTriangles(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices) const;

  /// The terms of eq. 4 along a path ([Brandt16 eq. 4]): W(x_s, x_s+1) + W(x_s+1, x_s) for every segment s
  /// (with x_n-1 -> x_0 if closed) and, with gradients, their derivatives summed per shape; without
  /// endGradients the ends of an open path get zero vectors instead (solvers that hold them fixed do not need
  /// them). The default evaluates both directions of every segment (in parallel on meshes of >= 1000
  /// vertices); an energy may share the work of one shape between both directions and both of its segments
  /// (DiscreteShells does). Throws InvalidInputError for fewer than 2 shapes and passes on the evaluations' errors.
  virtual std::vector<double> pathSegments(const std::vector<Eigen::VectorXd>& shapes, bool closed,
                                           std::vector<Eigen::VectorXd>* gradients, bool endGradients) const;

  /// sum_i w_i W[references_i, .] prepared for repeated evaluation, or null if this energy has no such form
  /// (the default; callers then sum the terms). The result refers to this energy, which must outlive it.
  /// `data` is empty or holds per reference referenceData(*references[i]) (or null: computed here).
  virtual std::unique_ptr<WeightedReferenceEnergy> weightedReferences(const std::vector<double>& weights,
                                                                      const std::vector<const Eigen::VectorXd*>& references,
                                                                      const std::vector<const ReferenceData*>& data) const;
  std::unique_ptr<WeightedReferenceEnergy> weightedReferences(const std::vector<double>& weights,
                                                              const std::vector<const Eigen::VectorXd*>& references) const {
    return weightedReferences(weights, references, {});
  }

  /// `shape`'s reference data for weightedReferences, or null if the energy keeps none (the default).
  /// Throws what weightedReferences throws for such a reference.
  virtual std::shared_ptr<const ReferenceData> referenceData(const Eigen::VectorXd& shape) const;

  /// Eq. 4 (the sum of pathSegments) from referenceData() of every path shape in path order, if this energy
  /// can compute it from that data alone (a caller that keeps the data saves a pass over every shape); the
  /// default cannot (nullopt).
  virtual std::optional<double> pathEnergy(const std::vector<const ReferenceData*>& data, bool closed) const;

protected:
  /// Throws InvalidInputError naming the argument if a shape has the wrong size or a non-finite entry.
  void checkShapes(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;
};

}  // namespace deformation_enrichment::shape_space
