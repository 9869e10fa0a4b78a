// triangleMeshFromCloud (ros_layer::triangleMeshFromMessage's core) on a PolygonMesh's vertex cloud and
// polygons (cloud_input.hpp).
#include "cloud_input.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/triangle_mesh_from_cloud.hpp"
#include "fuzz_support.hpp"

namespace de = deformation_enrichment;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto input = de::fuzz::decodeCloudInput(data, size, true);
  if (!input) return 0;
  try {
    const de::mesh::TriangleMesh mesh = de::mesh::triangleMeshFromCloud(
        input->layout, input->data.data(), input->data.size(), input->polygons,
        [](const std::vector<std::uint32_t>& polygon) -> const auto& { return polygon; });
    DE_FUZZ_CHECK(mesh.numVertices() > 0 && mesh.numTriangles() > 0);  // positions may be non-finite here
    DE_FUZZ_CHECK(mesh.triangles.minCoeff() >= 0 && mesh.triangles.maxCoeff() < mesh.numVertices());
  } catch (const de::InvalidInputError&) {
  }
  return 0;
}
