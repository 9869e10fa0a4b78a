#pragma once
// Triangle-mesh file I/O. OBJ, PLY (ASCII/binary) and ASCII OFF are read by the core's own readers
// (obj_reader.hpp, ply_reader.hpp, off_reader.hpp: PCL's and CGAL's crash or read out of bounds on
// malformed files), STL (ASCII/binary) by CGAL's polygon-soup reader; writing uses PCL. Polygons with more than three corners are split into triangle fans; vertices
// keep their file order (STL stores corners per triangle: CGAL merges identical ones in order of first
// use). Files without faces, with out-of-range indices or non-finite positions are rejected with an IoError
// that names the file and the problem. Duplicate vertices and zero-area triangles are kept: inspectSurface
// (surface_report.hpp) counts them.
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

enum class SurfaceFormat { Obj, Ply, Off, Stl };

/// The format of `path` by its extension (case-insensitive); throws IoError for any other extension.
SurfaceFormat surfaceFormatOf(const std::string& path);

/// Reads an .obj, .ply, .off or .stl file (chosen by extension).
TriangleMesh readTriangleMesh(const std::string& path);

/// Reads a surface of `format` from a stream (open it in binary mode); `name` names the source in errors,
/// which give the line (or, for binary STL, the byte) where parsing stopped. The path version calls this.
TriangleMesh readTriangleMesh(std::istream& in, SurfaceFormat format, const std::string& name);

/// Writes an .obj or .ply (binary) file, chosen by extension. Throws IoError on failure.
void writeTriangleMesh(const std::string& path, const TriangleMesh& mesh);

}  // namespace deformation_enrichment::mesh
