#pragma once
// PLY reader (readTriangleMesh's .ply half), ASCII and binary. Written here rather than taken from PCL:
// Debian's PCL keeps its assertions, and its PLY reader asserts, aborting the process, on malformed
// content (a vertex list property whose length changes, "alpha" without "red", ...) and sizes its
// buffers from the header's element counts.
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

/// Reads x, y, z of the `vertex` element (any numeric type) and the `face` element's vertex_indices (or
/// vertex_index) lists, fan-triangulated; other elements and properties are read past. Memory grows
/// with the data actually read, never with the header's counts. Throws IoError "<name>: ..." naming the
/// problem: a malformed header, missing x/y/z or face list, data that ends early or does not parse as
/// its type, a non-finite position, an index outside the vertices, no triangle.
TriangleMesh readPly(std::istream& in, const std::string& name);

}  // namespace deformation_enrichment::mesh
