#include "deformation_enrichment/mesh/volume_mesh_io.hpp"

#include <algorithm>
#include <cctype>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/gmsh_io.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"
#include "deformation_enrichment/mesh/vtk_io.hpp"

namespace deformation_enrichment::mesh {
namespace {

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

VolumeMeshFile readTetGenFile(const std::string& path) {
  TetGenMesh tetgen = readTetGen(path.substr(0, path.find_last_of('.')));
  VolumeMeshFile file;
  file.mesh = std::move(tetgen.mesh);
  file.region = std::move(tetgen.region);
  file.report.reorientedTets = tetgen.reorientedTets;
  file.report.unusedNodes = tetgen.unusedNodes;
  for (Eigen::Index v = 0; v < file.mesh.numVertices(); ++v) file.nodeIds.push_back(v + tetgen.indexBase);
  return file;
}

}  // namespace

VolumeFormat volumeFormatOf(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext == "node" || ext == "ele") return VolumeFormat::TetGen;
  if (ext == "msh") return VolumeFormat::Gmsh;
  if (ext == "vtk") return VolumeFormat::VtkLegacy;
  if (ext == "vtu") return VolumeFormat::VtkXml;
  throw IoError("volume mesh file '" + path + "' has an unsupported extension (expected .node/.ele, .msh, .vtk or .vtu)");
}

VolumeMeshFile readVolumeMesh(const std::string& path) {
  switch (volumeFormatOf(path)) {
    case VolumeFormat::TetGen: return readTetGenFile(path);
    case VolumeFormat::Gmsh: return readGmsh(path);
    case VolumeFormat::VtkLegacy:
    case VolumeFormat::VtkXml: return readVtk(path);
  }
  throw IoError("volume mesh file '" + path + "': unknown format");
}

std::string describe(const VolumeMeshFile& file) {
  std::string text = std::to_string(file.mesh.numVertices()) + " nodes, " + std::to_string(file.mesh.numTets()) + " tets";
  if (file.report.reorientedTets > 0) text += ", " + std::to_string(file.report.reorientedTets) + " reoriented";
  if (file.report.unusedNodes > 0) text += ", " + std::to_string(file.report.unusedNodes) + " nodes in no tet";
  for (const auto& [type, count] : file.report.skippedCells) text += ", skipped " + std::to_string(count) + " " + type;
  return text;
}

}  // namespace deformation_enrichment::mesh
