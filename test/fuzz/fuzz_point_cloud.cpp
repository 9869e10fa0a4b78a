// decodePositions (ros_layer::positionsFromCloud's core) on a PointCloud2 layout and data buffer
// (cloud_input.hpp); an accepted cloud must encode back into the very same bytes.
#include "cloud_input.hpp"
#include "deformation_enrichment/error.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto input = de::fuzz::decodeCloudInput(data, size, false);
  if (!input) return 0;
  const de::mesh::PointCloudLayout& layout = input->layout;
  try {
    const Eigen::Matrix3Xf positions = de::mesh::decodePositions(layout, input->data.data(), input->data.size());
    DE_FUZZ_CHECK(static_cast<std::uint64_t>(positions.cols()) == std::uint64_t(layout.width) * layout.height);
    std::vector<std::uint8_t> copy = input->data;
    de::mesh::encodePositions(positions, layout, copy.data(), copy.size());
    DE_FUZZ_CHECK(copy == input->data);
  } catch (const de::InvalidInputError&) {
  }
  return 0;
}
