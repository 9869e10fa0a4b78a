#pragma once
// Triangle-mesh file I/O (OBJ, PLY ASCII/binary). Reading uses the core's own readers (obj_reader.hpp,
// ply_reader.hpp; PCL's crash or abort on malformed files), writing uses PCL. Polygons with more than three
// corners are split into triangle fans; files without faces, with out-of-range indices or non-finite
// positions are rejected with an IoError that names the file and the problem.
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

/// Reads an .obj or .ply file (chosen by extension, case-insensitive).
TriangleMesh readTriangleMesh(const std::string& path);

/// Writes an .obj or .ply (binary) file, chosen by extension. Throws IoError on failure.
void writeTriangleMesh(const std::string& path, const TriangleMesh& mesh);

}  // namespace deformation_enrichment::mesh
