#pragma once
// Readers' errors must say where: expects an IoError whose message holds every fragment.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::test {

template <class Read>
void expectIoError(Read read, const std::vector<std::string>& fragments) {
  try {
    read();
    ADD_FAILURE() << "no IoError";
  } catch (const IoError& error) {
    for (const auto& fragment : fragments) EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

}  // namespace deformation_enrichment::test
