#pragma once
// A test whose data or tool is missing skips on a developer's machine and fails under CI=true: there
// scripts/install-deps and test/data provide everything, so a skip would hide a missing install step.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace deformation_enrichment::test {

inline bool underCi() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

}  // namespace deformation_enrichment::test

/// Ends the test: FAIL under CI=true, else SKIP, with `what` (a stream expression) as the message.
#define DE_MISSING_INPUT(what)                                                                               \
  do {                                                                                                       \
    if (::deformation_enrichment::test::underCi()) FAIL() << what << " (missing under CI=true: scripts/install-deps installs it)"; \
    GTEST_SKIP() << what;                                                                                    \
  } while (0)
