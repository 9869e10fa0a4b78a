#include "deformation_enrichment/mesh/vtk_io.hpp"

#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkIdList.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>

#include "deformation_enrichment/error.hpp"
#include "tet_collector.hpp"
#include "vtk_legacy_reader.hpp"

namespace deformation_enrichment::mesh {
namespace {

/// VTK reports problems of its readers, their XML parser and pipeline through the global output window
/// (printing them to stderr). While a file is read or written this window takes its place and keeps the
/// first error or warning; the mutex keeps concurrent calls of this library from sharing one window (VTK's
/// output window is process-wide).
class CapturingOutputWindow : public vtkOutputWindow {
public:
  static CapturingOutputWindow* New();
  vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow);

  // The base class logs each message (to stderr) before DisplayText: these replace it for problems.
  void DisplayErrorText(const char* text) override { keep(text); }
  void DisplayWarningText(const char* text) override { keep(text); }
  void DisplayGenericWarningText(const char* text) override { keep(text); }

  /// The first problem without VTK's "ERROR: In file, line N" and "Class (0x...): " prefixes.
  std::string first() const {
    std::string text = first_;
    const auto prefix = text.find("): ");
    if (prefix != std::string::npos) text.erase(0, prefix + 3);
    else if (text.find('\n') != std::string::npos) text.erase(0, text.find('\n') + 1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
    return text;
  }
  bool any() const { return !first_.empty(); }

private:
  void keep(const char* text) {
    if (first_.empty() && text) first_ = text;
  }
  std::string first_;
};
vtkStandardNewMacro(CapturingOutputWindow);

class VtkProblems {
public:
  // VTK also logs each problem to stderr before the window sees it: silenced meanwhile (with no log
  // files or callbacks registered, the cut-off is the stderr verbosity, which is restored).
  VtkProblems()
      : lock_(mutex()), previous_(vtkOutputWindow::GetInstance()), verbosity_(vtkLogger::GetCurrentVerbosityCutoff()) {
    vtkOutputWindow::SetInstance(window_);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~VtkProblems() {
    vtkLogger::SetStderrVerbosity(verbosity_);
    vtkOutputWindow::SetInstance(previous_);
  }
  VtkProblems(const VtkProblems&) = delete;
  VtkProblems& operator=(const VtkProblems&) = delete;

  /// Throws IoError("<what>: <VTK's message>") if VTK reported anything.
  void check(const std::string& what) const {
    if (window_->any()) throw IoError(what + ": " + window_->first());
  }

private:
  static std::mutex& mutex() {
    static std::mutex instance;
    return instance;
  }
  std::lock_guard<std::mutex> lock_;
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkLogger::Verbosity verbosity_;
  vtkNew<CapturingOutputWindow> window_;
};

bool isTet(int type) { return type == VTK_TETRA || type == VTK_QUADRATIC_TETRA || type == VTK_LAGRANGE_TETRAHEDRON; }

/// "vtkQuadraticTriangle" -> "quadraticTriangle".
std::string cellTypeName(int type) {
  const char* name = vtkCellTypes::GetClassNameFromTypeId(type);
  std::string text = name && std::string(name) != "UnknownClass" ? name : "cell type " + std::to_string(type);
  if (text.rfind("vtk", 0) == 0) text.erase(0, 3);
  if (!text.empty()) text[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
  return text;
}

/// The points and cells of a grid VTK's XML reader produced.
detail::VtkCells cellsOf(vtkUnstructuredGrid& grid) {
  detail::VtkCells cells;
  const vtkIdType pointCount = grid.GetNumberOfPoints();
  cells.points.resize(3, pointCount);
  for (vtkIdType p = 0; p < pointCount; ++p) grid.GetPoint(p, cells.points.col(p).data());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid.GetNumberOfCells(); ++c) {
    cells.types.push_back(grid.GetCellType(c));
    grid.GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) cells.connectivity.push_back(ids->GetId(k));
    cells.offsets.push_back(static_cast<long>(cells.connectivity.size()));
  }
  return cells;
}

VolumeMeshFile fromCells(detail::VtkCells cells, const std::string& name) {
  detail::TetCollector tets(name, "cell");
  for (std::size_t c = 0; c < cells.types.size(); ++c) {
    const int type = cells.types[c];
    if (!isTet(type)) {
      tets.skip(cellTypeName(type));
      continue;
    }
    const long* corners = cells.connectivity.data() + cells.offsets[c];
    const long count = cells.offsets[c + 1] - cells.offsets[c];
    if (count < 4) tets.fail(static_cast<long>(c), "tetrahedron has " + std::to_string(count) + " points");
    tets.add({corners[0], corners[1], corners[2], corners[3]}, 0, static_cast<long>(c));
  }
  std::vector<long> nodeIds(static_cast<size_t>(cells.points.cols()));
  for (std::size_t p = 0; p < nodeIds.size(); ++p) nodeIds[p] = static_cast<long>(p);
  return tets.finish(std::move(cells.points), std::move(nodeIds));
}

bool isXml(const std::string& path) {
  const VolumeFormat format = volumeFormatOf(path);
  if (format != VolumeFormat::VtkLegacy && format != VolumeFormat::VtkXml)
    throw IoError("VTK file '" + path + "' must end in .vtk (legacy) or .vtu (XML)");
  return format == VolumeFormat::VtkXml;
}

}  // namespace

VolumeMeshFile readVtk(std::istream& in, bool xml, const std::string& name) {
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw IoError("VTK file '" + name + "' cannot be read");
  if (bytes.empty()) throw IoError("VTK file '" + name + "' is empty");
  if (bytes.size() > static_cast<size_t>(INT_MAX)) throw IoError("VTK file '" + name + "' is larger than VTK reads from memory");
  detail::VtkCells cells;
  if (xml) {
    VtkProblems problems;
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->ReadFromInputStringOn();
    reader->SetInputString(bytes);
    reader->Update();
    problems.check("VTK file '" + name + "'");
    if (reader->GetOutput()) cells = cellsOf(*reader->GetOutput());
  } else {
    cells = detail::readVtkLegacy(bytes, name);
  }
  if (cells.points.cols() == 0) throw IoError("VTK file '" + name + "' has no points");
  return fromCells(std::move(cells), name);
}

VolumeMeshFile readVtk(const std::string& path) {
  const bool xml = isXml(path);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw IoError("cannot open VTK file " + path);
  return readVtk(file, xml, path);
}

void writeVtk(const std::string& path, const TetMesh& mesh) {
  const bool xml = isXml(path);
  validate(mesh, false);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(mesh.numVertices());
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v) points->SetPoint(v, mesh.vertices.col(v).data());
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->Allocate(mesh.numTets());
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const vtkIdType corners[4] = {mesh.tets(0, t), mesh.tets(1, t), mesh.tets(2, t), mesh.tets(3, t)};
    grid->InsertNextCell(VTK_TETRA, 4, corners);
  }
  VtkProblems problems;
  int written = 0;
  if (xml) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputData(grid);
    written = writer->Write();
  } else {
    vtkNew<vtkUnstructuredGridWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetFileTypeToBinary();
    writer->SetInputData(grid);
    written = writer->Write();
  }
  problems.check("VTK file '" + path + "' could not be written");
  if (!written) throw IoError("VTK file '" + path + "' could not be written");
}

}  // namespace deformation_enrichment::mesh
