#pragma once
// Object File Format (OFF) reader (readTriangleMesh's .off part). Written here rather than taken from CGAL:
// CGAL 5.5's OFF scanner sizes arrays from unchecked counts, casts out-of-range doubles to size_t and reads
// past a vertex line's entries for colours (all found by fuzz_off_stl), so an untrusted file could exhaust
// memory or read out of bounds.
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

/// Reads an ASCII OFF surface: the keyword `[ST][C][N][4]OFF`, the counts `vertices faces [edges]`, then
/// one vertex per line (x y z, and w for 4OFF; normals, colours and texture coordinates after them are
/// ignored) and one face per line (`n i_1 ... i_n`, an optional colour ignored), fan-triangulating
/// polygons; `#` starts a comment. Throws IoError "OFF file '<name>', line N: ..." for a malformed header,
/// count, vertex or face, an index outside the vertices or a non-finite position, and "OFF file '<name>':
/// ..." for binary OFF, nOFF (other dimensions) or a file without triangles.
TriangleMesh readOff(std::istream& in, const std::string& name);

}  // namespace deformation_enrichment::mesh
