// Writes a scene description back as a scene file (YAML), every key explicit: the provenance of a set.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <limits>

#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace deformation_enrichment::scene_file {
namespace {

// Emits `value` with enough digits to read back the same double.
YAML::Emitter& number(YAML::Emitter& out, double value) {
  out.SetDoublePrecision(std::numeric_limits<double>::max_digits10);
  return out << value;
}

void material(YAML::Emitter& out, const char* key, const Material& m) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "young" << YAML::Value;
  number(out, m.young);
  out << YAML::Key << "poisson" << YAML::Value;
  number(out, m.poisson);
  out << YAML::EndMap;
}

void vector3(YAML::Emitter& out, const Eigen::Vector3i& v) { out << YAML::Flow << YAML::BeginSeq << v.x() << v.y() << v.z() << YAML::EndSeq; }

std::string fileName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

void fixedRegion(YAML::Emitter& out, const FixedRegion& f, double units) {
  out << YAML::Key << "fixed" << YAML::Value << YAML::BeginMap;
  if (f.kind == FixedRegion::Kind::Vertices) {
    out << YAML::Key << "vertices" << YAML::Value << YAML::Flow << f.vertices;
  } else if (f.kind == FixedRegion::Kind::Box) {
    out << YAML::Key << "box" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (int k = 0; k < 3; ++k) number(out, f.boxLo(k) / units);
    for (int k = 0; k < 3; ++k) number(out, f.boxHi(k) / units);
    out << YAML::EndSeq;
  } else {
    out << YAML::Key << "below" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "axis" << YAML::Value
        << std::string(1, static_cast<char>('x' + f.axis)) << YAML::Key << "value" << YAML::Value;
    number(out, f.value / units);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

}  // namespace

std::string sceneYaml(const SceneDescription& s) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << s.name;
  out << YAML::Key << "units" << YAML::Value;
  number(out, s.units);
  if (s.procedural) {
    const Procedural& p = *s.procedural;
    static const char* shapes[] = {"slab", "pillow", "meniscus"};
    out << YAML::Key << "procedural" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "shape" << YAML::Value << shapes[static_cast<int>(p.shape)];
    out << YAML::Key << "coarse_cells" << YAML::Value;
    vector3(out, p.coarseCells);
    out << YAML::Key << "fine_cells" << YAML::Value;
    vector3(out, p.fineCells);
    out << YAML::Key << "coarse_skin_layers" << YAML::Value << p.coarseSkinLayers;
    out << YAML::Key << "fine_skin_layers" << YAML::Value << p.fineSkinLayers << YAML::EndMap;
  } else {
    out << YAML::Key << "surface" << YAML::Value << fileName(s.surface);
    if (!s.volume.empty()) out << YAML::Key << "volume" << YAML::Value << fileName(s.volume);
    if (s.coarseMaxVolume > 0.0) {
      out << YAML::Key << "coarse" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "max_volume" << YAML::Value;
      number(out, s.coarseMaxVolume) << YAML::EndMap;
    }
    if (s.fineMaxVolume > 0.0) {
      out << YAML::Key << "fine" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "max_volume" << YAML::Value;
      number(out, s.fineMaxVolume) << YAML::EndMap;
    }
  }
  material(out, "material", s.material);
  if (s.skin) {
    out << YAML::Key << "skin" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "thickness" << YAML::Value;
    number(out, s.skin->thickness) << YAML::Key << "young" << YAML::Value;
    number(out, s.skin->material.young) << YAML::Key << "poisson" << YAML::Value;
    number(out, s.skin->material.poisson);
    if (s.coarseSkinYoung) {
      out << YAML::Key << "coarse_young" << YAML::Value;
      number(out, *s.coarseSkinYoung);
    }
    out << YAML::EndMap;
  }
  if (s.fixed) fixedRegion(out, *s.fixed, s.units);
  out << YAML::Key << "tool" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "model" << YAML::Value
      << (s.tool.model == ToolModel::Penalty ? "penalty" : "dirichlet") << YAML::Key << "radius" << YAML::Value;
  number(out, s.tool.radius) << YAML::Key << "stiffness" << YAML::Value;
  number(out, s.tool.stiffness) << YAML::EndMap;
  out << YAML::Key << "solve" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "indent_steps" << YAML::Value
      << s.solve.indentSteps << YAML::Key << "drag_steps" << YAML::Value << s.solve.dragSteps << YAML::Key
      << "relative_tolerance" << YAML::Value;
  number(out, s.solve.relativeTolerance) << YAML::EndMap;
  out << YAML::Key << "stamp" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "radius" << YAML::Value;
  number(out, s.stamp.radius) << YAML::Key << "resolution" << YAML::Value << s.stamp.resolution << YAML::Key << "layers"
                              << YAML::Value << s.stamp.layers << YAML::EndMap;
  out << YAML::Key << "descriptors" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "window_scale"
      << YAML::Value;
  number(out, s.descriptors.windowScale) << YAML::Key << "cutoff" << YAML::Value;
  number(out, s.descriptors.cutoff) << YAML::Key << "sample_spacing" << YAML::Value;
  number(out, s.descriptors.sampleSpacing) << YAML::Key << "quadrature" << YAML::Value
                                           << (s.descriptors.averageQuadrature ? "average" : "volume") << YAML::EndMap;
  out << YAML::Key << "max_outside" << YAML::Value;
  number(out, s.maxOutside);
  out << YAML::Key << "plan" << YAML::Value << (s.plan == "auto" ? s.plan : fileName(s.plan));
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace deformation_enrichment::scene_file
