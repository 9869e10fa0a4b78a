#include "deformation_enrichment/mesh/image_surface.hpp"

#include <vtkCleanPolyData.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkImageGaussianSmooth.h>
#include <vtkMarchingCubes.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataConnectivityFilter.h>
#include <vtkSmartPointer.h>
#include <vtkQuadricDecimation.h>
#include <vtkTriangleFilter.h>
#include <vtkWindowedSincPolyDataFilter.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"

namespace deformation_enrichment::mesh {
namespace {

/// The 0/1 object field cropped to the object's bounding box plus a margin of empty voxels (so the
/// contour closes and the smoothing has room), with its origin at the crop's corner.
vtkSmartPointer<vtkImageData> objectField(const LabelImage& image, int minLabel, int margin) {
  Eigen::Vector3i lo = image.size, hi = -Eigen::Vector3i::Ones();
  for (int z = 0; z < image.size.z(); ++z)
    for (int y = 0; y < image.size.y(); ++y)
      for (int x = 0; x < image.size.x(); ++x)
        if (image.at(x, y, z) >= minLabel) {
          lo = lo.cwiseMin(Eigen::Vector3i(x, y, z));
          hi = hi.cwiseMax(Eigen::Vector3i(x, y, z));
        }
  if (hi.x() < 0) throw InvalidInputError("imageSurface: no voxel has a label >= " + std::to_string(minLabel));
  lo.array() -= margin;
  const Eigen::Vector3i dims = (hi - lo).array() + 1 + margin;
  auto field = vtkSmartPointer<vtkImageData>::New();
  field->SetDimensions(dims.x(), dims.y(), dims.z());
  field->SetSpacing(image.spacing.data());
  field->SetOrigin(lo.x() * image.spacing.x(), lo.y() * image.spacing.y(), lo.z() * image.spacing.z());
  vtkNew<vtkFloatArray> values;
  values->SetNumberOfValues(vtkIdType(dims.prod()));
  vtkIdType i = 0;
  for (int z = lo.z(); z < lo.z() + dims.z(); ++z)
    for (int y = lo.y(); y < lo.y() + dims.y(); ++y)
      for (int x = lo.x(); x < lo.x() + dims.x(); ++x) {
        const bool inImage = x >= 0 && y >= 0 && z >= 0 && x < image.size.x() && y < image.size.y() && z < image.size.z();
        values->SetValue(i++, inImage && image.at(x, y, z) >= minLabel ? 1.0f : 0.0f);
      }
  field->GetPointData()->SetScalars(values);
  return field;
}

TriangleMesh toMesh(vtkPolyData& polygons) {
  TriangleMesh mesh;
  mesh.vertices.resize(3, polygons.GetNumberOfPoints());
  for (vtkIdType p = 0; p < polygons.GetNumberOfPoints(); ++p) polygons.GetPoint(p, mesh.vertices.col(p).data());
  mesh.triangles.resize(3, polygons.GetNumberOfPolys());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < polygons.GetNumberOfPolys(); ++c) {
    polygons.GetCellPoints(c, ids);
    for (int k = 0; k < 3; ++k) mesh.triangles(k, c) = int(ids->GetId(k));
  }
  // Marching cubes orients by the field's gradient: flip if the enclosed volume comes out negative.
  double volume = 0.0;
  for (Eigen::Index t = 0; t < mesh.numTriangles(); ++t) {
    Eigen::Matrix3d corners;
    for (int k = 0; k < 3; ++k) corners.col(k) = mesh.vertices.col(mesh.triangles(k, t));
    volume += corners.determinant();
  }
  if (volume < 0.0) mesh.triangles.row(1).swap(mesh.triangles.row(2));
  return mesh;
}

}  // namespace

TriangleMesh imageSurface(const LabelImage& image, const ImageSurfaceOptions& options) {
  if (!(options.smoothingSigma >= 0.0) || options.targetVertices < 4 || options.smoothingIterations < 0 ||
      !(options.isoValue > 0.0 && options.isoValue < 1.0))
    throw InvalidInputError("imageSurface: smoothingSigma and smoothingIterations must be non-negative, "
                            "targetVertices >= 4 and isoValue in (0, 1)");
  const Eigen::Vector3d sigma = options.smoothingSigma * image.spacing.cwiseInverse();  // in voxels
  const int margin = 2 + int(std::ceil(3.0 * sigma.maxCoeff()));
  vtkSmartPointer<vtkImageData> field = objectField(image, options.minLabel, margin);

  vtkNew<vtkImageGaussianSmooth> smooth;
  smooth->SetInputData(field);
  smooth->SetDimensionality(3);
  smooth->SetStandardDeviations(std::max(sigma.x(), 1e-6), std::max(sigma.y(), 1e-6), std::max(sigma.z(), 1e-6));
  smooth->SetRadiusFactors(3.0, 3.0, 3.0);
  vtkNew<vtkMarchingCubes> contour;
  contour->SetInputConnection(smooth->GetOutputPort());
  contour->SetValue(0, options.isoValue);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  vtkNew<vtkPolyDataConnectivityFilter> largest;
  largest->SetInputConnection(contour->GetOutputPort());
  largest->SetExtractionModeToLargestRegion();
  vtkNew<vtkCleanPolyData> clean;  // connectivity keeps unused points
  clean->SetInputConnection(largest->GetOutputPort());
  clean->PointMergingOff();
  clean->Update();
  const double points = double(clean->GetOutput()->GetNumberOfPoints());

  vtkNew<vtkQuadricDecimation> decimate;
  decimate->SetInputConnection(clean->GetOutputPort());
  decimate->SetTargetReduction(std::clamp(1.0 - options.targetVertices / points, 0.0, 0.999));
  decimate->VolumePreservationOn();
  vtkNew<vtkWindowedSincPolyDataFilter> sinc;
  sinc->SetInputConnection(decimate->GetOutputPort());
  sinc->SetNumberOfIterations(options.smoothingIterations);
  sinc->SetPassBand(0.05);
  sinc->NormalizeCoordinatesOn();
  sinc->BoundarySmoothingOff();
  sinc->FeatureEdgeSmoothingOff();
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(options.smoothingIterations > 0 ? sinc->GetOutputPort() : decimate->GetOutputPort());
  triangles->Update();

  TriangleMesh surface = toMesh(*triangles->GetOutput());
  const SurfaceReport report = inspectSurface(surface);
  if (!report.closedManifold() || report.degenerateTriangles > 0 || report.unusedVertices > 0)
    throw NumericalError("imageSurface: the filtered surface is not a clean closed manifold: " + describe(report));
  return surface;
}

}  // namespace deformation_enrichment::mesh
