#pragma once
// Triangle-mesh file I/O by libraries: OBJ and PLY (ASCII/binary) through PCL, OFF and STL (ASCII/binary)
// through CGAL's polygon-soup readers. Polygons with more than three corners are split into triangle
// fans; vertices keep their file order (STL stores corners per triangle: CGAL merges identical ones in
// order of first use). Files without faces, with out-of-range indices or non-finite positions are rejected
// with an IoError that names the file and the problem. Duplicate vertices and zero-area triangles are
// kept: inspectSurface (surface_report.hpp) counts them.
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

enum class SurfaceFormat { Obj, Ply, Off, Stl };

/// The format of `path` by its extension (case-insensitive); throws IoError for any other extension.
SurfaceFormat surfaceFormatOf(const std::string& path);

/// Reads an .obj, .ply, .off or .stl file (chosen by extension).
TriangleMesh readTriangleMesh(const std::string& path);

/// Reads OFF or STL from a stream (open STL streams in binary mode); `name` names the source in errors,
/// which give the line (or, for binary STL, the byte) where parsing stopped. The path version calls this.
/// PCL reads OBJ and PLY from files only, so for those formats this throws InvalidInputError.
TriangleMesh readTriangleMesh(std::istream& in, SurfaceFormat format, const std::string& name);

/// Writes an .obj or .ply (binary) file, chosen by extension. Throws IoError on failure.
void writeTriangleMesh(const std::string& path, const TriangleMesh& mesh);

}  // namespace deformation_enrichment::mesh
