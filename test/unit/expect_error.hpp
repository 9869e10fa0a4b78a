#pragma once
// Shared by the unit tests: an expected error whose message must name the problem.
#include <gtest/gtest.h>

#include <string>

/// Expects `run()` to throw `Error` whose message contains `fragment`.
template <class Error, class Run>
void expectErrorContaining(Run run, const std::string& fragment) {
  try {
    run();
    ADD_FAILURE() << "no error (expected: " << fragment << ")";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}
