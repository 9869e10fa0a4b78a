// The frame path of EnrichmentSession: a state in, its enriched positions out (docs/design.md §6). The
// configuration side is session_configuration.cpp (example sets, knobs) and session_rest_worker.cpp (rest surfaces).
#include <cmath>

#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_state.hpp"
#include "session_built.hpp"

namespace deformation_enrichment::enrichment {
std::shared_ptr<const RestSurface> EnrichmentSession::restFor(Eigen::Index vertices) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (active_ && active_->geometry.surface.numVertices() == vertices) return active_;
  if (pending_ && pending_->geometry.surface.numVertices() == vertices) return pending_;
  return nullptr;
}

void EnrichmentSession::enrichContacts(const Eigen::Matrix3Xf& positions, const std::vector<Contact>& contacts, double dt) {
  enricher_->enricher->enrich(positions, contacts, scratch_, ContactEnricher::StateCheck::Skip);  // enrich() checked it
  SurfaceEnrichment& touched = scratch_.enrichment;
  temporalFilter_.filter(touched, dt, positions.cols());  // a dt <= 0 (stamps going backwards) restarts it
  enriched_ = positions;
  bool finite = true;  // the input is finite: only the touched vertices can have become non-finite
  for (std::size_t k = 0; k < touched.vertices.size(); ++k) {
    auto vertex = enriched_.col(touched.vertices[k]);
    vertex += touched.displacements.col(static_cast<Eigen::Index>(k)).cast<float>();
    finite &= vertex.allFinite();
  }
  if (!finite) {
    temporalFilter_.reset();
    throw NumericalError("enrichment produced a non-finite position");
  }
  continuity_.update(scratch_);
  result_.kind = FrameResult::Kind::Enriched;
  result_.changed = !touched.vertices.empty();
  result_.verticesTouched = static_cast<std::uint32_t>(touched.vertices.size());
  result_.releasedSites = static_cast<std::uint32_t>(continuity_.releasedSites());
  for (const ContactOutcome& outcome : scratch_.contacts) {
    result_.confidence = std::max(result_.confidence, static_cast<float>(outcome.confidence));
    for (Eigen::Index i = 0; i < outcome.weights.size(); ++i) {
      if (std::abs(outcome.weights[i]) < 1e-3) continue;  // report the examples that matter
      result_.exampleIds.push_back(static_cast<std::uint32_t>(i));
      result_.weights.push_back(static_cast<float>(outcome.weights[i]));
    }
  }
}

const FrameResult& EnrichmentSession::enrich(const Eigen::Matrix3Xf& positions, const std::vector<ToolContact>& touching,
                                             double stampSeconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  const bool onActive = active_ && active_->geometry.surface.numVertices() == positions.cols();
  const bool onPending = !onActive && pending_ && pending_->geometry.surface.numVertices() == positions.cols();
  if (!onActive && !onPending) {
    const RestSurface* newest = pending_ ? pending_.get() : active_.get();
    throw InvalidInputError(newest ? "mesh state has " + std::to_string(positions.cols()) + " points but the rest mesh has " +
                                         std::to_string(newest->geometry.surface.numVertices())
                                   : std::string("no rest surface yet"));
  }
  mesh::validateMeshState(positions, positions.cols());  // before the stream's memory moves on
  const bool enriching = onActive && enricher_ && enricher_->enricher;
  const double dt = lastStamp_ ? stampSeconds - *lastStamp_ : 0.0;
  lastStamp_ = stampSeconds;

  // Tools in contact, then the sites released tools left deformed; a fading filter needs states too.
  std::vector<Contact> contacts;
  if (enriching) {
    std::vector<Contact> tools;
    for (const ToolContact& tool : touching) {
      Contact contact;
      contact.point = tool.point;
      contact.restState = false;  // contacts live in the current (mesh-state) frame
      contact.toolId = toolNumbers_.emplace(tool.toolId, static_cast<int>(toolNumbers_.size())).first->second;
      tools.push_back(contact);
    }
    contacts = continuity_.contactsFor(tools);
  }
  if (contacts.empty() && !(enriching && temporalFilter_.fading())) {
    result_ = FrameResult();
    result_.restPending = onPending;
    if (!touching.empty())
      result_.note = onPending ? "the enricher of the new rest surface is being built" : "no example set loaded";
    temporalFilter_.reset();  // nothing enriched: a later contact starts the filter afresh
    memo_.invalidate();
    return result_;
  }
  // A fading temporal filter moves the output on every state: nothing to reuse then.
  if (temporalFilter_.timeConstant() <= 0.0 && memo_.matches(positions, contacts, configVersion_, active_->version)) {
    result_.kind = FrameResult::Kind::Reused;
    ++stats_.statesReused;
    return result_;
  }
  result_ = FrameResult();
  memo_.invalidate();
  try {
    enrichContacts(positions, contacts, dt);
  } catch (const Error& e) {
    result_ = FrameResult();
    result_.error = e.what();
    return result_;
  }
  memo_.remember(positions, std::move(contacts), configVersion_, active_->version);
  return result_;
}

}  // namespace deformation_enrichment::enrichment
