#include "deformation_enrichment/descriptors/descriptor_distance.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::descriptors {

namespace {
void checkFinite(const hermite::MomentList& a, const hermite::MomentList& b, const char* what) {
  if (!a.values().allFinite() || !b.values().allFinite())
    throw InvalidInputError(std::string(what) + ": descriptor contains NaN or Inf");
  if (a.firstOrder() != b.firstOrder() || a.lastOrder() != b.lastOrder() || a.channels() != b.channels())
    throw InvalidInputError(std::string(what) + ": descriptors have different orders or channels");
}
}  // namespace

double siteDistance(const hermite::MomentList& rho, const hermite::MomentList& rhoOther) {
  checkFinite(rho, rhoOther, "d_rho");
  hermite::MomentList difference = rho;
  difference.values() -= rhoOther.values();
  return hermite::norm(difference);  // eq. (9)
}

double deformationDistance(const hermite::MomentList& mu, const hermite::MomentList& muOther) {
  checkFinite(mu, muOther, "d_u");
  const double norm = hermite::norm(mu);
  const double normOther = hermite::norm(muOther);
  if (norm == 0.0 && normOther == 0.0) return 0.0;
  if (norm == 0.0 || normOther == 0.0) return 1.0;
  // eq. (14) on normalised moments, so tiny descriptors cannot underflow the product of norms.
  hermite::MomentList a = mu, b = muOther;
  a.values() /= norm;
  b.values() /= normOther;
  return std::clamp(1.0 - hermite::inner(a, b), 0.0, 2.0);
}

}  // namespace deformation_enrichment::descriptors
