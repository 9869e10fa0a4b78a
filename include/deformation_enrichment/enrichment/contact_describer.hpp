#pragma once
// The descriptors of one tool contact on a rest surface ([Seiler14 §5]): the contact located on the current
// surface and mapped to the rest state, the site descriptor rho (density moments of the site density, eq. 7;
// cached per rest vertex and interpolated over the contact's triangle), the deformation descriptor mu (MLS
// "surface samples" mode over the surface vertices near the contact, rest vs current, completed by the
// normals; eq. 10-11) and the stamping frame B (normal, rho_1, then the deformation direction; Appendix B).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"
#include "deformation_enrichment/descriptors/stamping_frame.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::enrichment {

/// One tool contact. `point` is a rest-state position when `restState`, otherwise a current-state position,
/// mapped to the rest state through its nearest point on the current surface (barycentric on the triangle
/// there, so a sliding contact moves continuously instead of snapping from vertex to vertex).
struct Contact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  bool restState = true;
  std::optional<Eigen::Vector3d> normal;  ///< outward normal in rest axes; default: the interpolated rest normal
  int toolId = 0;
  /// b_x of this contact's previous frame: the stamping frame's last resort, so it does not jump (a stream).
  std::optional<Eigen::Vector3d> previousFrameAxis;
  /// > 0: a released site (the tool lifted off) whose detail fades with |mu| / releasedMagnitude, the
  /// deformation then. Magnitude-aware stamps fade by themselves and ignore it.
  double releasedMagnitude = 0.0;
};

/// Descriptors of one contact, exactly what an example stores (rho, mu in frame B) plus what mapping needs.
struct ContactDescription {
  int vertex = -1;                                        ///< the rest vertex of the contact's triangle nearest to it
  Eigen::Vector3i corners = Eigen::Vector3i::Constant(-1);  ///< the triangle the contact lies on
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();  ///< of the contact on `corners` (>= 0, sum 1)
  Eigen::Vector3d p = Eigen::Vector3d::Zero();            ///< rest-state contact position
  Eigen::Matrix3d B = Eigen::Matrix3d::Identity();        ///< stamping frame (rest axes)
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();        ///< polar rotation of the MLS F (rest -> current)
  descriptors::FrameRule frameRule = descriptors::FrameRule::Fixed;
  hermite::MomentList rho;                                ///< in frame B
  hermite::MomentList mu;                                 ///< in frame B
};

class ContactDescriber {
public:
  /// `restSurface`: a valid triangle mesh (zero-area triangles allowed). `siteDensity`: the samples of the
  /// material around it for rho (descriptors::siteDensity); none: the interior of the rest surface sampled
  /// every `sampleSpacing` (0: h / 4), which must then be closed. Throws InvalidInputError for an invalid
  /// surface or an open one without density samples.
  ContactDescriber(mesh::TriangleMesh restSurface, const descriptors::DescriptorOptions& options, double sampleSpacing,
                   std::optional<descriptors::PointSampling> siteDensity);

  const mesh::TriangleMesh& restSurface() const { return rest_; }
  const Eigen::Matrix3Xd& restNormals() const { return restNormals_; }

  /// The descriptors of `contact` on the state `current` (3 x vertices, Matrix3Xd or Matrix3Xf, checked by
  /// the caller: right size, finite). Throws InvalidInputError for a non-finite contact or a contact with no
  /// surface vertex within the window cut-off. Fills caches of rest-state quantities (site descriptors,
  /// windows): not for concurrent calls.
  template <typename Positions>
  ContactDescription describe(const Positions& current, const Contact& contact) const;

private:
  /// The vertex of `current` nearest to `point` (the first of equals).
  template <typename Positions>
  int nearestVertex(const Positions& current, const Eigen::Vector3d& point) const;
  /// Places the contact on the surface `positions` (rest or current): the nearest point among the triangles
  /// around `vertex` (its nearest vertex), written to d.corners, d.barycentric and d.vertex.
  template <typename Positions>
  void locate(const Positions& positions, int vertex, const Eigen::Vector3d& point, ContactDescription& d) const;
  /// rho at a rest vertex (world axes), computed once per vertex.
  const hermite::MomentList& siteMoments(int vertex) const;
  template <typename Positions>
  Eigen::Vector3d currentNormal(const Positions& current, int vertex) const;
  /// The deformation descriptor's window at rest point p (cached, see recentWindows_).
  const descriptors::Window& surfaceWindow(const Eigen::Vector3d& p) const;

  descriptors::DescriptorOptions options_;
  mesh::TriangleMesh rest_;
  Eigen::Matrix3Xd restNormals_;
  std::vector<std::vector<int>> vertexTriangles_;
  std::unique_ptr<descriptors::DescriptorEvaluator> siteEvaluator_;  // interior sampling (rho, normals)
  std::unique_ptr<descriptors::PointSampling> surfaceSampling_;      // surface vertices, area weights (mu)
  mutable std::vector<std::optional<hermite::MomentList>> siteCache_;  // rho (world axes) per rest vertex
  mutable std::array<std::optional<descriptors::Window>, 4> recentWindows_;  // last windows (a few tools)
  mutable std::size_t nextWindow_ = 0;
  mutable Eigen::ArrayXf floatDistances_;    // nearestVertex's scratch
  mutable Eigen::ArrayXd doubleDistances_;
};

extern template ContactDescription ContactDescriber::describe(const Eigen::Matrix3Xd&, const Contact&) const;
extern template ContactDescription ContactDescriber::describe(const Eigen::Matrix3Xf&, const Contact&) const;

}  // namespace deformation_enrichment::enrichment
