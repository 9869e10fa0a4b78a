#pragma once
// The run-time pipeline of [Seiler14 §5-§6] on one rest surface, shared by the ROS node, acquisition and
// evaluation so that example descriptors and run-time descriptors are computed by the same code:
//   per contact p: site descriptor rho (density moments of the site density: by default an interior sampling
//   of the closed rest surface, or the samples the caller gives (descriptors/site_density.hpp: a volume or a
//   shell for an open surface); cached per rest vertex and interpolated over the contact's triangle), deformation descriptor mu (MLS "surface samples" mode over
//   the surface vertices near p, rest vs current, completed by the rest/current normals), stamping frame
//   B (normal, rho_1, then the deformation direction), then ExampleBlender (eq. 15 -> RBF -> eq. 16) and
//   StampMapper (eq. 1, multi-contact rim rule).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"
#include "deformation_enrichment/enrichment/example_blender.hpp"
#include "deformation_enrichment/enrichment/stamp_blending.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::enrichment {

/// How much of the blended detail is applied: the run-time knobs stamp_gain and min_confidence.
struct DetailGain {
  double stampGain = 1.0;  ///< scales every blended stamp; >= 0
  /// Detail fades in with the blend's confidence (paper: max eq. 15 weight; regression: the variance the
  /// examples explain): 0 below minConfidence, full from 2 minConfidence on, smoothstep between (a ramp,
  /// not a step). 0 = never gated; in [0, 1].
  double minConfidence = 0.0;
  /// Throws InvalidInputError naming the value out of range.
  void check() const;
};

struct ContactEnricherOptions {
  descriptors::DescriptorOptions descriptors;  ///< window scale h, orders N, frame tolerance, MLS
  double stampRadius = 0.02;    ///< R of the stamps this surface expects (m); examples must match
  double sampleSpacing = 0.0;   ///< interior sampling for rho (m); 0 = h / 4
  /// StampMapper rim band. Measured on held-out slab contacts (R = 3 cm): enriched / coarse RMS 0.34 with
  /// no band (but a seam at the rim), 0.38 with 0.1, 0.42 with 0.2: the band fades real detail.
  double rimBand = 0.1;
  /// Magnitude-aware stamps (docs/design.md §4): eq. (16) becomes Psi = sum_i w~_i (|mu| / |mu[i]|) Psi[i], so an
  /// example's detail scales with how strongly the current contact deforms compared with the example
  /// (eq. 14 compares directions only). false = the paper's pure correlation. Measured on held-out slab
  /// contacts: enriched / coarse RMS 0.49 with, 0.53 without (R = 2 cm, band 0.2); 0.34 vs 0.45 (band 0).
  bool magnitudeAware = true;
  /// Bounds of the blend, so a contact far outside the examples gets neither large weights (the paper
  /// blend's unclamped weights reach +-5 there) nor an unlimited magnitude. Blend paper: |mu| / |mu[i]| is
  /// clamped to maxMagnitudeRatio and every w~_i to [-maxWeight, maxWeight]. Blend regression (its weights
  /// fade away from the examples' sites by themselves): no clamp; |mu| counts at most maxMagnitudeRatio
  /// times the largest |mu[i]|. All bounds are continuous, so a stream stays continuous.
  double maxMagnitudeRatio = 2.0;
  double maxWeight = 2.0;
  DetailGain gain;  ///< the run-time knobs (times the set's material similarity in a session)
};

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

struct ContactOutcome {
  int toolId = 0;
  ContactDescription description;
  Eigen::VectorXd weights;  ///< w~ per example (eq. 16)
  double confidence = 0.0;  ///< the blend's confidence (paper: max eq. (15) weight; regression: explained variance)
  double muNorm = 0.0;      ///< |mu|: how strongly the tissue is deformed at the contact
  double detailScale = 1.0; ///< confidence ramp times the fade of a released site (times the stamp gain)
};

struct EnrichmentTimings {
  double descriptorSeconds = 0.0, blendSeconds = 0.0, mapSeconds = 0.0, totalSeconds = 0.0;
};

struct EnrichmentResult {
  SurfaceEnrichment enrichment;  ///< touched vertex ids (ascending) and added displacements
  std::vector<ContactOutcome> contacts;
  EnrichmentTimings timings;
};

class ContactEnricher {
public:
  /// `restSurface`: a valid triangle mesh (zero-area triangles allowed). `siteDensity`: the samples of the
  /// material around it for rho (descriptors::siteDensity); none: the interior of the rest surface, which
  /// must then be closed. Throws InvalidInputError for an invalid surface, an open one without density
  /// samples, or bad options (non-positive radius, scale, spacing).
  ContactEnricher(mesh::TriangleMesh restSurface, const ContactEnricherOptions& options,
                  std::optional<descriptors::PointSampling> siteDensity = std::nullopt);
  ~ContactEnricher();
  ContactEnricher(ContactEnricher&&) noexcept;
  ContactEnricher& operator=(ContactEnricher&&) noexcept;

  const ContactEnricherOptions& options() const { return options_; }
  const mesh::TriangleMesh& restSurface() const { return rest_; }
  Eigen::Index size() const { return rest_.vertices.cols(); }

  /// Builds the ExampleBlender for `set` (widths fitted at load). The stamps' radius must equal
  /// options().stampRadius. On an exception the previous examples stay active.
  void setExamples(const examples::ExampleSet& set, const ExampleBlenderOptions& blenderOptions = {});
  bool hasExamples() const { return blender_ != nullptr; }
  const ExampleBlender* blender() const { return blender_.get(); }
  /// options().gain at run time; throws InvalidInputError (DetailGain::check) and keeps the old one.
  void setDetailGain(const DetailGain& gain);
  /// Kernel widths of eq. (15) for the active set (run-time knob): a positive width replaces the current
  /// one, 0 or a negative one restores the width the set was loaded with (leave-one-out fitted, or given).
  /// Rebuilds the RBF interpolator, O(N^3) in the examples. Throws InvalidInputError without examples or
  /// for a non-finite width; the old widths stay then.
  void setKernelWidths(double sigmaRho, double sigmaU);
  /// The widths the active set was loaded with (before any setKernelWidths).
  const KernelWidths& loadedWidths() const { return loadedWidths_; }

  /// Descriptors at one contact for the current surface positions (3 x size()). Throws InvalidInputError
  /// for wrong sizes, NaN, or a contact with no surface vertex within the window cut-off.
  /// Fills caches of rest-state quantities (site descriptors, windows): not for concurrent calls.
  ContactDescription describe(const Eigen::Matrix3Xd& current, const Contact& contact) const;

  /// Enrichment of the current state for the contacts. No contact: empty result, nothing evaluated.
  /// Vertices outside every stamp radius are not listed. Needs examples (else InvalidInputError).
  /// Reuses internal scratch: one enricher must not be used from two threads at once. `check` = Skip for a
  /// caller that has already checked the state's size and finiteness (a pass over every vertex saved).
  enum class StateCheck { Full, Skip };
  void enrich(const Eigen::Matrix3Xd& current, const std::vector<Contact>& contacts, EnrichmentResult& out,
              StateCheck check = StateCheck::Full);
  /// The same for a single-precision state (a mesh-state message's points), read where it is needed
  /// instead of widened as a whole.
  void enrich(const Eigen::Matrix3Xf& current, const std::vector<Contact>& contacts, EnrichmentResult& out,
              StateCheck check = StateCheck::Full);

  /// e of one stamp alone placed at a described contact (eq. 1, the rim rule): what that stamp adds there,
  /// for error bounds that compare stamps with the truth. Shares enrich()'s scratch (same thread rules).
  void placeStamp(const ContactDescription& description, const cv::Mat& stamp, double radius, int layers, SurfaceEnrichment& out);

  /// s~ = s + e (eq. 1) in place; untouched vertices keep their bits.
  void apply(const EnrichmentResult& result, Eigen::Matrix3Xd& state) const { mapper_.apply(result.enrichment, state); }

private:
  /// Both enrich() overloads (Positions: Matrix3Xd or Matrix3Xf).
  template <typename Positions>
  void enrichState(const Positions& current, const std::vector<Contact>& contacts, EnrichmentResult& out, StateCheck check);
  /// describe() for a state that passed checkState().
  template <typename Positions>
  ContactDescription describeValidState(const Positions& current, const Contact& contact) const;
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
  /// Blends one described contact's stamp (eq. 15 -> RBF -> eq. 16, bounded and scaled) into `stamp`.
  void blendContact(const Contact& contact, ContactOutcome& outcome, ContactStamp& stamp);
  /// The deformation descriptor's window at rest point p (cached, see recentWindows_).
  const descriptors::Window& surfaceWindow(const Eigen::Vector3d& p) const;
  template <typename Positions>
  void checkState(const Positions& current, StateCheck check = StateCheck::Full) const;

  ContactEnricherOptions options_;
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
  std::shared_ptr<ExampleBlender> blender_;
  KernelWidths loadedWidths_;     // of the active set, as fitted at load
  std::vector<cv::Mat> stamps_;   // the active set's stamps (magnitude-aware blending)
  Eigen::VectorXd muNorms_;       // |mu[i]| of the active set
  StampMapper mapper_;
  BlendResult blendScratch_;
  std::vector<ContactStamp> stampScratch_;
};

}  // namespace deformation_enrichment::enrichment
