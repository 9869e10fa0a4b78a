#pragma once
// Symmetric 3D tensors stored by their distinct components (multiIndices() order): full-tensor expansion,
// the generalized dot product of [Seiler14 Appendix A], and basis transformation of Appendix B.
#include <Eigen/Core>

namespace deformation_enrichment::hermite {

/// Expands distinct components to all 3^n entries (entry index i1 3^(n-1) + ... + in).
Eigen::VectorXd toFullTensor(int order, const Eigen::Ref<const Eigen::VectorXd>& distinct);

/// Reads the distinct components from a full 3^n tensor (taking the sorted index tuple of each component;
/// the tensor is assumed symmetric).
Eigen::VectorXd fromFullTensor(int order, const Eigen::Ref<const Eigen::VectorXd>& full);

/// Full-tensor dot product (Appendix A, eq. 17 with M = N): sum over all 3^n tuples, which equals
/// sum_alpha multiplicity(alpha) a_alpha b_alpha on distinct components.
double fullTensorDot(int order, const Eigen::Ref<const Eigen::VectorXd>& a,
                     const Eigen::Ref<const Eigen::VectorXd>& b);

/// Linear map on distinct components implementing Appendix B, G'_{i1..in} = sum_j G_{j1..jn} T_{i1 j1}..T_{in jn}:
/// distinct(G') = symmetricTransform(n, T) * distinct(G). To express a world tensor in a frame B (columns =
/// frame axes) use T = B^T. Throws InvalidInputError for a non-finite T.
Eigen::MatrixXd symmetricTransform(int order, const Eigen::Matrix3d& T);

/// Appendix B applied to one tensor.
Eigen::VectorXd transformTensor(int order, const Eigen::Ref<const Eigen::VectorXd>& distinct,
                                const Eigen::Matrix3d& T);

}  // namespace deformation_enrichment::hermite
