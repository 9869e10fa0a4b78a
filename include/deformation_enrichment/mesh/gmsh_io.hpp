#pragma once
// gmsh's MSH files, versions 2.2 and 4.1, ASCII and binary, and the ASCII version 1.0 that SOFA's meshes use
// ([gmsh], "MSH file format"), read into a
// tet mesh. Written here because Debian's gmsh library (libgmsh-dev) is GPL-2+ and its exception covers
// only combining gmsh with TetGen, Netgen, Chaco, METIS and OpenCASCADE, not linking it into this
// BSD-3 package; the reader is tested against files written by Debian's gmsh executable.
//
// Read: $MeshFormat (absent in 1.0, which has $NOD and $ELM with the physical region as an element's first
// region tag), $Entities (4.1: a volume's first physical tag becomes its tets' region), $Nodes and
// $Elements; other sections ($PhysicalNames, $Periodic, post-processing data, ...) are skipped. Tets of
// any order (types 4, 11, 29, 30, 31) keep their four corners; other elements are counted by family.
// Binary files must be little-endian with 8-byte doubles (what gmsh writes on x86 and ARM).
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/volume_mesh_io.hpp"

namespace deformation_enrichment::mesh {

/// Reads a .msh file. Throws IoError naming the file and the line (ASCII) or byte offset (binary).
VolumeMeshFile readGmsh(const std::string& path);

/// The same from a stream opened in binary mode (the path version calls this); `name` names it in errors.
VolumeMeshFile readGmsh(std::istream& in, const std::string& name);

}  // namespace deformation_enrichment::mesh
