// bullet_coarse_sim_node: a coarse soft-tissue simulator on Bullet's deformable bodies (bullet_engine/
// bullet_tissue.hpp) that speaks the coarse-simulator contract of docs/coarse_simulator.md, for any scene
// file: it publishes the display surface's states on `mesh_state` (the surface attached barycentrically to
// the scene's coarse volume) and the surface on `rest_mesh` (latched), takes the tool sphere's centre on
// `servo_cp` and returns the tissue to rest on `reset`. It stands for a user's own simulator (AMBF runs Bullet)
// when examples are made against it (acquisition_driver) and when the enrichment node enriches its stream.
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "deformation_enrichment/bullet_engine/bullet_tissue.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"
#include "deformation_enrichment/ros/parameter.hpp"

namespace de = deformation_enrichment;
using de::ros_layer::requiredTypeParameter;

namespace {

// Without ~time_step, the mesh's stable step (bullet_engine::stableTimeStep); without ~steps_per_state, the
// steps that make about a millisecond of simulated time per state.
constexpr double kSimulatedSecondsPerState = 1e-3;

struct NodeOptions {
  std::string scene, frame;
  double rate = 60.0;
  std::optional<int> stepsPerState;
  std::optional<double> timeStep;
  de::bullet_engine::BulletTissueOptions tissue;
};

// ~ parameters, each positive and finite; throws std::runtime_error naming a bad one.
NodeOptions readSettings(ros::NodeHandle& pnh) {
  NodeOptions s;
  s.scene = requiredTypeParameter<std::string>(pnh, "scene", "slab");
  s.frame = requiredTypeParameter<std::string>(pnh, "frame_id", "slab");
  s.rate = requiredTypeParameter(pnh, "rate", s.rate);
  if (pnh.hasParam("steps_per_state")) s.stepsPerState = requiredTypeParameter(pnh, "steps_per_state", 0);
  if (pnh.hasParam("time_step")) s.timeStep = requiredTypeParameter(pnh, "time_step", 0.0);
  s.tissue.density = requiredTypeParameter(pnh, "density", s.tissue.density);
  s.tissue.damping = requiredTypeParameter(pnh, "damping", s.tissue.damping);
  s.tissue.massDamping = requiredTypeParameter(pnh, "mass_damping", s.tissue.massDamping);
  s.tissue.toolSpeed = requiredTypeParameter(pnh, "tool_speed", s.tissue.toolSpeed);
  for (const auto& [name, value] : {std::pair<const char*, double>{"rate", s.rate}, {"time_step", s.timeStep.value_or(1.0)},
                                    {"density", s.tissue.density}, {"damping", s.tissue.damping}, {"tool_speed", s.tissue.toolSpeed},
                                    {"steps_per_state", s.stepsPerState.value_or(1)}})
    if (!(value > 0.0) || !std::isfinite(value)) throw std::runtime_error(std::string("~") + name + " must be positive and finite, got " + std::to_string(value));
  return s;
}

class BulletCoarseSim {
public:
  BulletCoarseSim(ros::NodeHandle& nh, const NodeOptions& settings) : settings_(settings) {
    const de::scene_file::SceneDescription scene = de::scene_file::readSceneFile(de::scene_file::findSceneFile(settings.scene));
    models_ = de::scenes::buildSceneModels(scene);
    de::bullet_engine::BulletTissueOptions options = settings.tissue;
    options.young = scene.material.young;
    options.poisson = scene.material.poisson;
    options.toolRadius = scene.tool.radius;
    options.timeStep = settings.timeStep.value_or(
        de::bullet_engine::stableTimeStep(models_.coarse.mesh, options.young, options.poisson, options.density));
    stepsPerState_ = settings.stepsPerState.value_or(std::max(1, static_cast<int>(std::lround(kSimulatedSecondsPerState / options.timeStep))));
    tissue_ = std::make_unique<de::bullet_engine::BulletTissue>(models_.coarse.mesh, models_.coarse.fixedVertices, options);
    embedding_ = de::mesh::embedPoints(models_.coarse.mesh, models_.surface.vertices, scene.maxOutside);
    header_.frame_id = settings.frame;
    header_.stamp = ros::Time::now();
    restPub_ = nh.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, /*latch=*/true);
    restPub_.publish(de::ros_layer::messageFromTriangleMesh(models_.surface, header_));
    statePub_ = nh.advertise<sensor_msgs::PointCloud2>("mesh_state", 10);
    measuredPub_ = nh.advertise<geometry_msgs::PoseStamped>("measured_cp", 10);
    commands_ = nh.subscribe("servo_cp", 10, &BulletCoarseSim::onCommand, this);
    reset_ = nh.advertiseService("reset", &BulletCoarseSim::onReset, this);
    ROS_INFO("bullet coarse sim: scene %s, %ld nodes, %ld tets, %ld display vertices; E %g Pa, nu %g (Bullet Neo-Hookean, one "
             "material, no skin), density %g kg/m^3, damping %g s and %g 1/s; tool radius %g m at up to %g m/s; %d steps of %g s per "
             "state at %g Hz",
             scene.name.c_str(), static_cast<long>(models_.coarse.mesh.numVertices()), static_cast<long>(models_.coarse.mesh.numTets()),
             static_cast<long>(models_.surface.numVertices()), options.young, options.poisson, options.density, options.damping, options.massDamping,
             options.toolRadius, options.toolSpeed, stepsPerState_, options.timeStep, settings.rate);
  }

  void tick() {
    // A blown-up Bullet state (non-finite, or a node farther from rest than the body is large) is never
    // published: step() has put the tissue back to rest and parked the tool.
    if (!tissue_->step(stepsPerState_))
      ROS_ERROR("bullet coarse sim: Bullet blew up (%ld times so far): the tissue is back at rest, the tool parked",
                tissue_->divergences());
    const Eigen::Matrix3Xd nodes = tissue_->positions();
    const de::mesh::TetMesh& rest = models_.coarse.mesh;
    const Eigen::Matrix3Xd surface = models_.surface.vertices + de::mesh::interpolate(embedding_, rest, nodes - rest.vertices);
    header_.stamp = ros::Time::now();
    statePub_.publish(de::ros_layer::cloudFromPositions(surface.cast<float>(), header_));
    // Where the tool is: it follows servo_cp at ~tool_speed.
    measuredPub_.publish(de::ros_layer::poseAt(tissue_->toolCentre(), header_));
  }

private:
  void onCommand(const geometry_msgs::PoseStamped& pose) {
    const Eigen::Vector3d centre(pose.pose.position.x, pose.pose.position.y, pose.pose.position.z);
    if (!centre.allFinite() || (!pose.header.frame_id.empty() && pose.header.frame_id != settings_.frame)) {
      ++refused_;
      const std::string why = centre.allFinite() ? "frame '" + pose.header.frame_id + "', not '" + settings_.frame + "'"
                                                 : std::string("non-finite position");
      ROS_WARN_THROTTLE(1.0, "bullet coarse sim: servo_cp refused (%d so far): %s", refused_, why.c_str());
      return;
    }
    tissue_->setToolCentre(centre);
  }

  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    tissue_->reset();
    return true;
  }

  NodeOptions settings_;
  de::scenes::SceneModels models_;
  std::unique_ptr<de::bullet_engine::BulletTissue> tissue_;
  de::mesh::BarycentricEmbedding embedding_;
  std_msgs::Header header_;
  ros::Publisher restPub_, statePub_, measuredPub_;
  ros::Subscriber commands_;
  ros::ServiceServer reset_;
  int stepsPerState_ = 1;
  int refused_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "bullet_coarse_sim");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<BulletCoarseSim> sim;
  NodeOptions settings;
  try {
    settings = readSettings(pnh);
    sim = std::make_unique<BulletCoarseSim>(nh, settings);
  } catch (const std::exception& e) {
    ROS_FATAL("bullet coarse sim: %s", e.what());
    return 1;
  }
  ros::WallRate loop(settings.rate);  // ticks per wall second, also under use_sim_time
  while (ros::ok()) {
    ros::spinOnce();
    sim->tick();
    loop.sleep();
  }
  return 0;
}
