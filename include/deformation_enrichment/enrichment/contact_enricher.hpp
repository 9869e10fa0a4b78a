#pragma once
// The run-time pipeline of [Seiler14 §5-§6] on one rest surface, shared by the ROS node, acquisition and
// evaluation so that example descriptors and run-time descriptors are computed by the same code: per contact
// its descriptors (ContactDescriber: rho, mu, frame B; the site density by default an interior sampling of
// the closed rest surface, or the samples the caller gives, descriptors/site_density.hpp), then
// ExampleBlender (eq. 15 -> RBF -> eq. 16) and StampMapper (eq. 1, multi-contact rim rule).
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "deformation_enrichment/enrichment/contact_describer.hpp"
#include "deformation_enrichment/enrichment/example_blender.hpp"
#include "deformation_enrichment/enrichment/stamp_blending.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::enrichment {

/// How much of the blended detail is applied: the run-time knobs stamp_gain, min_confidence and max_weight_norm.
struct DetailGain {
  double stampGain = 1.0;  ///< scales every blended stamp; >= 0
  /// Detail fades in with the blend's confidence (paper: max eq. 15 weight; regression: the variance the
  /// examples explain): 0 below minConfidence, full from 2 minConfidence on, smoothstep between (a ramp,
  /// not a step). 0 = never gated; in [0, 1].
  double minConfidence = 0.0;
  /// Blend regression: the detail is scaled by min(1, maxWeightNorm / sum_i |w_i|). Weights that must be
  /// large and cancel to fit a contact are an extrapolation (transfer to another shape, a contact unlike
  /// every example); most in-scene contacts stay below 4 (docs/accuracy.md). 0 = no bound; >= 0. The paper's
  /// blend has its own bound on each weight (ContactEnricherOptions::maxWeight) and ignores this one.
  double maxWeightNorm = 4.0;
  /// Throws InvalidInputError naming the value out of range.
  void check() const;
  /// The same knobs with the stamp gain multiplied by `factor` (a set's material similarity).
  DetailGain withStampGainTimes(double factor) const;
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

struct ContactOutcome {
  int toolId = 0;
  ContactDescription description;
  Eigen::VectorXd weights;  ///< w~ per example (eq. 16)
  double confidence = 0.0;  ///< the blend's confidence (paper: max eq. (15) weight; regression: explained variance)
  double muNorm = 0.0;      ///< |mu|: how strongly the tissue is deformed at the contact
  double detailScale = 1.0; ///< confidence ramp, weight-norm bound and fade of a released site (times the stamp gain)
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
  const mesh::TriangleMesh& restSurface() const { return describer_.restSurface(); }
  Eigen::Index size() const { return restSurface().vertices.cols(); }

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
  /// Blends one described contact's stamp (eq. 15 -> RBF -> eq. 16, bounded and scaled) into `stamp`.
  void blendContact(const Contact& contact, ContactOutcome& outcome, ContactStamp& stamp);
  template <typename Positions>
  void checkState(const Positions& current, StateCheck check = StateCheck::Full) const;

  ContactEnricherOptions options_;
  ContactDescriber describer_;  // owns the rest surface
  std::shared_ptr<ExampleBlender> blender_;
  KernelWidths loadedWidths_;     // of the active set, as fitted at load
  std::vector<cv::Mat> stamps_;   // the active set's stamps (magnitude-aware blending)
  Eigen::VectorXd muNorms_;       // |mu[i]| of the active set
  StampMapper mapper_;
  BlendResult blendScratch_;
  std::vector<ContactStamp> stampScratch_;
};

}  // namespace deformation_enrichment::enrichment
