// shape_space_server: services that smooth recorded deformation sequences in shape space, compute geodesics
// and Bezier curves between meshes of one topology ([Brandt16]). Meshes travel as PointCloud2 vertex arrays
// over one shared triangle list. Bad input gets success = false and a message naming the problem.
#include <ros/ros.h>

#include <chrono>
#include <cmath>
#include <string>

#include "deformation_enrichment/BezierCurve.h"
#include "deformation_enrichment/ComputeGeodesic.h"
#include "deformation_enrichment/SmoothSequence.h"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#include "deformation_enrichment/shape_space/blas_threads.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/geodesic.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"
#include "deformation_enrichment/ros/parameter.hpp"

namespace de = deformation_enrichment;
using de::ros_layer::parameter;
namespace ss = de::shape_space;

namespace {

class ShapeSpaceServer {
public:
  explicit ShapeSpaceServer(ros::NodeHandle privateNh) {
    const std::string membrane = parameter<std::string>(privateNh, "membrane", "hyperelastic");
    classic_ = membrane == "discrete_shells";
    if (!classic_ && membrane != "hyperelastic") ROS_ERROR("unknown ~membrane '%s', using 'hyperelastic'", membrane.c_str());
    bendingWeight_ = parameter(privateNh, "bending_weight", 0.0, [](double v) { return v >= 0.0 && std::isfinite(v); }, ">= 0");
    maxShapes_ = parameter(privateNh, "max_shapes", 2000, [](int v) { return v >= 1; }, ">= 1");
    smooth_ = privateNh.advertiseService("smooth_sequence", &ShapeSpaceServer::smooth, this);
    geodesic_ = privateNh.advertiseService("compute_geodesic", &ShapeSpaceServer::geodesic, this);
    bezier_ = privateNh.advertiseService("bezier_curve", &ShapeSpaceServer::bezier, this);
  }

private:
  static Eigen::Matrix3Xi triangles(const pcl_msgs::PolygonMesh& topology, Eigen::Index numVertices) {
    const Eigen::Matrix3Xi result = de::mesh::fanTriangulate(
        topology.polygons, numVertices, [](const pcl_msgs::Vertices& p) -> const auto& { return p.vertices; });
    if (result.cols() == 0) throw de::InvalidInputError("topology has no triangles");
    return result;
  }

  static Eigen::VectorXd shape(const sensor_msgs::PointCloud2& cloud, const std::string& name) {
    try {
      return ss::flatten(de::ros_layer::positionsFromCloud(cloud).cast<double>());
    } catch (const de::Error& e) {
      throw de::InvalidInputError(name + ": " + e.what());
    }
  }

  static sensor_msgs::PointCloud2 cloud(const Eigen::VectorXd& flat, const std_msgs::Header& header) {
    return de::ros_layer::cloudFromPositions(ss::unflatten(flat).cast<float>(), header);
  }

  ss::ShapeSequence sequence(const pcl_msgs::PolygonMesh& topology, const std::vector<sensor_msgs::PointCloud2>& clouds,
                             int minShapes) const {
    if (clouds.size() > static_cast<size_t>(maxShapes_))
      throw de::InvalidInputError("too many shapes: " + std::to_string(clouds.size()) + " > ~max_shapes");
    if (clouds.size() < static_cast<size_t>(minShapes))
      throw de::InvalidInputError("need at least " + std::to_string(minShapes) + " shapes, got " +
                                  std::to_string(clouds.size()));
    ss::ShapeSequence result;
    for (size_t i = 0; i < clouds.size(); ++i) result.shapes.push_back(shape(clouds[i], "shape " + std::to_string(i)));
    result.triangles = triangles(topology, result.numVertices());
    ss::validateSequence(result, minShapes);
    return result;
  }

  // The shell energy of a request: ~bending_weight when positive, else scaled to the mesh's size from its
  // first shape as de_smooth and de_smooth_bag do (DiscreteShellsOptions::hyperelasticFor).
  ss::DiscreteShellsOptions parametersFor(const Eigen::VectorXd& firstShape) const {
    if (classic_) return ss::DiscreteShellsOptions::classic();
    return bendingWeight_ > 0.0 ? ss::DiscreteShellsOptions::hyperelastic(bendingWeight_)
                                : ss::DiscreteShellsOptions::hyperelasticFor(firstShape);
  }

  template <class Response, class Work>
  bool serve(const char* what, Response& response, Work work) {
    const auto start = std::chrono::steady_clock::now();
    try {
      response.message = work();  // "ok", or what the caller should know (e.g. a stalled flow)
      response.success = true;
    } catch (const de::Error& e) {
      response.success = false;
      response.message = e.what();
      ROS_ERROR("%s failed: %s", what, e.what());
    }
    response.seconds = de::secondsSince(start);
    return true;  // the service call itself succeeded; success says whether the work did
  }

  bool smooth(de::SmoothSequence::Request& request, de::SmoothSequence::Response& response) {
    return serve("smooth_sequence", response, [&] {
      ss::ShapeSequence input = sequence(request.topology, request.shapes, 3);
      const ss::DiscreteShells energy(input.triangles, input.numVertices(), parametersFor(input.shapes.front()));
      ss::FlowOptions options;
      options.tau = request.tau > 0.0 ? request.tau : 0.5;
      options.rho = request.restoring;
      options.closed = request.closed;
      options.reduction.reduced = request.subspace > 0;
      if (options.reduction.reduced) options.reduction.subspaceDimension = static_cast<int>(request.subspace);
      options.parallelShapes = true;  // DiscreteShells is thread-safe; the Jacobi update makes shapes independent
      ss::SmoothingFlow flow(energy, std::move(input), options);
      response.path_energy.push_back(flow.pathEnergy());
      int unconverged = 0;
      std::string message = "ok";
      for (uint32_t k = 0; k < request.iterations; ++k) {
        const ss::FlowStep step = flow.step();
        if (step.stalled) {  // no tau lowers eq. 4: later steps would stall the same way
          message = "stalled after " + std::to_string(k) + " steps (no tau lowers the path energy)";
          break;
        }
        unconverged += step.unconvergedAverages;
        // step.pathEnergy is of the ghost shapes if a ghost mesh is used
        response.path_energy.push_back(flow.ghostVertices() > 0 ? flow.pathEnergy() : step.pathEnergy);
      }
      if (unconverged > 0) message += ", " + std::to_string(unconverged) + " averages did not converge (last iterates used)";
      for (size_t i = 0; i < request.shapes.size(); ++i)
        response.shapes.push_back(cloud(flow.current().shapes[i], request.shapes[i].header));
      return message;
    });
  }

  bool geodesic(de::ComputeGeodesic::Request& request, de::ComputeGeodesic::Response& response) {
    return serve("compute_geodesic", response, [&] {
      const Eigen::VectorXd a = shape(request.start, "start"), b = shape(request.end, "end");
      if (a.size() != b.size()) throw de::InvalidInputError("start and end have different vertex counts");
      const Eigen::Matrix3Xi tris = triangles(request.topology, a.size() / 3);
      const ss::DiscreteShells energy(tris, a.size() / 3, parametersFor(a));
      ss::GeodesicOptions options;
      options.shapes = static_cast<int>(request.shapes);
      options.reduction.reduced = request.subspace > 0;
      if (options.reduction.reduced) options.reduction.subspaceDimension = static_cast<int>(request.subspace);
      const ss::GeodesicResult result = ss::geodesic(energy, tris, a, b, options);
      response.path_energy = result.pathEnergyHistory;
      response.length = result.length;
      for (const auto& s : result.shapes) response.shapes.push_back(cloud(s, request.start.header));
      return std::string("ok");
    });
  }

  bool bezier(de::BezierCurve::Request& request, de::BezierCurve::Response& response) {
    return serve("bezier_curve", response, [&] {
      const ss::ShapeSequence controls = sequence(request.topology, request.controls, 2);
      if (request.samples < 2) throw de::InvalidInputError("need at least 2 samples");
      const ss::DiscreteShells energy(controls.triangles, controls.numVertices(), parametersFor(controls.shapes.front()));
      ss::GeodesicOptions options;
      options.shapes = request.shapes_per_geodesic > 0 ? static_cast<int>(request.shapes_per_geodesic) : 8;
      const auto curve =
          ss::bezierCurve(energy, controls.triangles, controls.shapes, static_cast<int>(request.samples), options);
      for (const auto& s : curve) response.shapes.push_back(cloud(s, request.controls.front().header));
      return std::string("ok");
    });
  }

  bool classic_ = false;
  double bendingWeight_ = 0.0;  ///< 0: scaled to each request's mesh size
  int maxShapes_ = 2000;
  ros::ServiceServer smooth_, geodesic_, bezier_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "shape_space_server");
  ss::preferSingleThreadedBlas();
  ShapeSpaceServer server(ros::NodeHandle("~"));
  ros::spin();
  return 0;
}
