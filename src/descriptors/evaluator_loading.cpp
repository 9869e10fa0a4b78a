#include "deformation_enrichment/descriptors/evaluator_loading.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "deformation_enrichment/descriptors/interior_sampling.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"

namespace deformation_enrichment::descriptors {

namespace {
std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string extension = path.substr(dot + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}
}  // namespace

LoadedObject loadDescriptorObject(const std::string& path, const DescriptorOptions& options,
                                  double surfaceSampleSpacing) {
  const std::string extension = lowerExtension(path);
  if (extension == "node") {
    const mesh::TetGenMesh tetgen = mesh::readTetGen(path.substr(0, path.size() - 5));
    std::ostringstream how;
    how << "tet mesh vertices (" << tetgen.mesh.numVertices() << ") with lumped volumes";
    return LoadedObject{DescriptorEvaluator(tetgen.mesh, options), true, how.str()};
  }
  if (extension == "obj" || extension == "ply") {
    mesh::TriangleMesh surface = mesh::readTriangleMesh(path);
    const double spacing = surfaceSampleSpacing > 0.0 ? surfaceSampleSpacing : options.window.scale / 4.0;
    PointSampling samples = sampleClosedSurfaceInterior(surface, spacing);
    std::ostringstream how;
    how << "interior grid of closed surface, spacing " << spacing << " m, " << samples.size()
        << " samples (ray-parity inside test, cell volumes)";
    return LoadedObject{DescriptorEvaluator(std::move(samples), std::move(surface), {}, options), false, how.str()};
  }
  throw InvalidInputError("unsupported mesh file '" + path + "' (expected .node, .obj or .ply)");
}

}  // namespace deformation_enrichment::descriptors
