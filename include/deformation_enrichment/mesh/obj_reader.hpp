#pragma once
// Wavefront OBJ geometry reader (readTriangleMesh's .obj half). Written here rather than taken from PCL:
// PCL's OBJ reader indexes token lists without bounds checks and throws std::out_of_range on malformed
// statements, so an untrusted file could crash or corrupt the process.
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

/// Reads `v x y z [w]` vertices and `f` faces (corners `i`, `i/t`, `i//n`, `i/t/n`; a negative index
/// counts back from the last vertex read), fan-triangulating polygons; comments (#) and every other
/// statement (vt, vn, g, o, s, l, usemtl, mtllib, ...) are skipped. Throws IoError "<name>:<line>: ..."
/// for a malformed or non-finite vertex, a malformed face corner or an index outside the vertices, and
/// "<name>: ..." for a file without vertices or triangles.
TriangleMesh readObj(std::istream& in, const std::string& name);

}  // namespace deformation_enrichment::mesh
