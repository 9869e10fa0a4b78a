#pragma once
// What EnrichmentSession builds for one rest surface and configuration (private to the session's sources).
#include <cstdint>
#include <memory>
#include <string>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"

namespace deformation_enrichment::enrichment {

struct EnrichmentSession::Built {
  std::unique_ptr<ContactEnricher> enricher;  ///< null without an example set
  std::string siteDensity;                    ///< how rho's samples were made
  double materialSimilarity = 1.0;            ///< of the set's scene and SessionOptions::scene
  double stampScale = 1.0;                    ///< scales the stamps: the similarity or SessionOptions::transferGain
  std::uint64_t restVersion = 0, configVersion = 0;
};

}  // namespace deformation_enrichment::enrichment
