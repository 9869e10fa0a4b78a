#pragma once
// VTK unstructured grids ([VTK], "VTK File Formats"): XML .vtu read by vtkXMLUnstructuredGridReader (ASCII,
// binary or appended data, compressed or not); legacy .vtk (ASCII or binary, format versions 2.0-5.1) read
// by the core's checked reader (src/mesh/vtk_legacy_reader: VTK 9.1's reads past corrupt arrays); both
// written by VTK's writers. Point i is node i;
// tetrahedra (linear, quadratic and Lagrange: corners first) are kept, other cells counted by type.
#include <iosfwd>
#include <string>

#include "deformation_enrichment/mesh/volume_mesh_io.hpp"

namespace deformation_enrichment::mesh {

/// Reads a .vtk or .vtu file (by extension). Throws IoError naming the file and VTK's message, or the cell.
VolumeMeshFile readVtk(const std::string& path);

/// The same from a stream holding a whole file (the path version calls this); `xml` picks .vtu over
/// legacy .vtk, `name` names the source in errors.
VolumeMeshFile readVtk(std::istream& in, bool xml, const std::string& name);

/// Writes a tet mesh as .vtk (legacy, binary) or .vtu (XML, appended, compressed) by extension, for
/// ParaView and for other programs' readers. Throws IoError if the file cannot be written.
void writeVtk(const std::string& path, const TetMesh& mesh);

}  // namespace deformation_enrichment::mesh
