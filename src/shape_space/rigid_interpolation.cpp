#include "deformation_enrichment/shape_space/rigid_interpolation.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/kabsch.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"

namespace deformation_enrichment::shape_space {

RigidTransform kabsch(const Eigen::VectorXd& from, const Eigen::VectorXd& to) {
  if (from.size() != to.size() || from.size() % 3 != 0 || from.size() == 0)
    throw InvalidInputError("kabsch: position vectors must be non-empty, equally long and multiples of 3");
  const kinematics::RigidTransform fit = kinematics::kabsch(unflatten(from), unflatten(to));
  RigidTransform motion;
  motion.rotation = fit.R;
  motion.translation = fit.t;
  return motion;
}

Eigen::VectorXd applyRigid(const RigidTransform& motion, const Eigen::VectorXd& positions) {
  Eigen::Matrix3Xd p = unflatten(positions);
  p = (motion.rotation * p).colwise() + motion.translation;
  return flatten(p);
}

Eigen::VectorXd alignPieces(const Eigen::VectorXd& shape, const Eigen::VectorXd& target,
                            const std::vector<std::vector<int>>& pieces) {
  if (shape.size() != target.size() || shape.size() % 3 != 0)
    throw InvalidInputError("align pieces: shapes must be equally long multiples of 3");
  Eigen::VectorXd out = shape;
  for (const std::vector<int>& piece : pieces) {
    Eigen::Matrix3Xd from(3, Eigen::Index(piece.size())), to(3, Eigen::Index(piece.size()));
    for (size_t k = 0; k < piece.size(); ++k) {
      if (piece[k] < 0 || 3 * Eigen::Index(piece[k]) >= shape.size())
        throw InvalidInputError("align pieces: vertex index " + std::to_string(piece[k]) + " out of range");
      from.col(Eigen::Index(k)) = shape.segment<3>(3 * piece[k]);
      to.col(Eigen::Index(k)) = target.segment<3>(3 * piece[k]);
    }
    const kinematics::RigidTransform fit = kinematics::kabsch(from, to);
    for (size_t k = 0; k < piece.size(); ++k) out.segment<3>(3 * piece[k]) = fit.R * from.col(Eigen::Index(k)) + fit.t;
  }
  return out;
}

Eigen::VectorXd rigidAwareInterpolation(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double t) {
  if (!(t >= 0.0 && t <= 1.0)) throw InvalidInputError("interpolation parameter must lie in [0, 1]");
  if (t == 0.0) return a;
  if (t == 1.0) return b;
  const RigidTransform ab = kabsch(a, b);
  const Eigen::Matrix3Xd pa = unflatten(a);
  const Eigen::Vector3d ca = pa.rowwise().mean();
  const Eigen::Matrix3Xd pb = unflatten(b);
  const Eigen::Vector3d cb = pb.rowwise().mean();
  // b brought back into a's frame (about its centroid), blended with a, then rotated by the partial rotation.
  const Eigen::Matrix3Xd bInA = ab.rotation.transpose() * (pb.colwise() - cb);
  const Eigen::Matrix3Xd blended = (1.0 - t) * (pa.colwise() - ca) + t * bInA;
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity().slerp(t, Eigen::Quaterniond(ab.rotation));
  const Eigen::Matrix3Xd out = (q.toRotationMatrix() * blended).colwise() + ((1.0 - t) * ca + t * cb);
  return flatten(out);
}

}  // namespace deformation_enrichment::shape_space
