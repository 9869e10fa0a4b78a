#include "deformation_enrichment/scene_file/scene_description.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::scene_file {
namespace {

namespace fs = std::filesystem;

// Reads one YAML map of a scene file: typed values with messages naming file, line and key, and a final
// check that every key was known.
class MapReader {
public:
  MapReader(const YAML::Node& node, const std::string& file, const std::string& prefix)
      : node_(node), file_(file), prefix_(prefix) {
    if (!node_.IsMap()) fail(node_, prefix_.empty() ? "the scene must be a YAML map" : "must be a map");
  }

  bool has(const std::string& key) const { return static_cast<bool>(node_[key]); }
  YAML::Node node(const std::string& key) {
    used_.insert(key);
    return node_[key];
  }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& problem, const std::string& key = "") const {
    const std::string name = prefix_ + (prefix_.empty() || key.empty() ? "" : ".") + key;
    throw InvalidInputError(file_ + ":" + std::to_string(at.Mark().line + 1) + ": " + (name.empty() ? "" : "'" + name + "' ") +
                            problem);
  }

  [[noreturn]] void failHere(const std::string& problem) const { fail(node_, problem); }

  double number(const std::string& key, double fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = node(key);
    double value = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, value) || !std::isfinite(value))
      fail(n, "must be a finite number", key);
    return value;
  }
  double positive(const std::string& key, double fallback) {
    const double value = number(key, fallback);
    if (!(value > 0.0)) fail(node_[key], "must be positive, got " + std::to_string(value), key);
    return value;
  }
  int integer(const std::string& key, int fallback, int minimum) {
    if (!has(key)) return fallback;
    const YAML::Node n = node(key);
    int value = 0;
    if (!n.IsScalar() || !YAML::convert<int>::decode(n, value)) fail(n, "must be an integer", key);
    if (value < minimum) fail(n, "must be at least " + std::to_string(minimum) + ", got " + std::to_string(value), key);
    return value;
  }
  std::string text(const std::string& key, const std::string& fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = node(key);
    if (!n.IsScalar()) fail(n, "must be a string", key);
    return n.Scalar();
  }
  std::vector<double> numbers(const std::string& key, std::size_t count) {
    const YAML::Node n = node(key);
    if (!n.IsSequence() || n.size() != count) fail(n, "must be a list of " + std::to_string(count) + " numbers", key);
    std::vector<double> values;
    for (const YAML::Node& item : n) {
      double value = 0.0;
      if (!item.IsScalar() || !YAML::convert<double>::decode(item, value) || !std::isfinite(value))
        fail(item, "must hold finite numbers only", key);
      values.push_back(value);
    }
    return values;
  }
  MapReader map(const std::string& key) { return MapReader(node(key), file_, prefix_ + (prefix_.empty() ? "" : ".") + key); }

  // Every key of the map must have been read.
  void finish() const {
    for (const auto& entry : node_) {
      if (!entry.first.IsScalar()) fail(entry.first, "has a key that is not a plain name");  // e.g. {a: 1, {b: 2}}
      const std::string key = entry.first.Scalar();
      if (!used_.count(key)) fail(entry.first, "is not a known key", key);
    }
  }

private:
  YAML::Node node_;
  std::string file_, prefix_;
  std::set<std::string> used_;
};

// A file named by the scene, relative to the scene file's folder; it must exist.
std::string existingFile(MapReader& reader, const std::string& key, const fs::path& folder, const std::string& sceneFile) {
  const std::string value = reader.text(key, "");
  if (value.empty()) reader.fail(reader.node(key), "must name a file", key);
  const fs::path path = fs::path(value).is_absolute() ? fs::path(value) : folder / value;
  if (!fs::is_regular_file(path)) throw IoError(sceneFile + ": '" + key + "' names " + path.string() + ", which does not exist");
  return fs::absolute(path).lexically_normal().string();
}

Material readMaterial(MapReader reader) {
  Material m;
  m.young = reader.positive("young", 0.0);
  m.poisson = reader.number("poisson", 0.45);
  if (!(m.poisson > -1.0 && m.poisson < 0.5))
    reader.fail(reader.node("poisson"), "must lie in (-1, 0.5), got " + std::to_string(m.poisson), "poisson");
  reader.finish();
  return m;
}

FixedRegion readFixed(MapReader reader, double units) {
  FixedRegion fixed;
  const int given = reader.has("vertices") + reader.has("box") + reader.has("below");
  if (given != 1) reader.failHere("needs exactly one of 'vertices', 'box', 'below'");
  if (reader.has("vertices")) {
    fixed.kind = FixedRegion::Kind::Vertices;
    const YAML::Node list = reader.node("vertices");
    if (!list.IsSequence() || list.size() == 0) reader.fail(list, "must be a non-empty list of node ids", "vertices");
    for (const YAML::Node& item : list) {
      int id = -1;
      if (!item.IsScalar() || !YAML::convert<int>::decode(item, id) || id < 0) reader.fail(item, "must hold ids >= 0", "vertices");
      fixed.vertices.push_back(id);
    }
  } else if (reader.has("box")) {
    fixed.kind = FixedRegion::Kind::Box;
    const std::vector<double> b = reader.numbers("box", 6);
    fixed.boxLo = units * Eigen::Vector3d(b[0], b[1], b[2]);
    fixed.boxHi = units * Eigen::Vector3d(b[3], b[4], b[5]);
    if (!(fixed.boxLo.array() < fixed.boxHi.array()).all()) reader.fail(reader.node("box"), "needs x0 < x1, y0 < y1, z0 < z1", "box");
  } else {
    fixed.kind = FixedRegion::Kind::Below;
    MapReader below = reader.map("below");
    const std::string axis = below.text("axis", "z");
    if (axis != "x" && axis != "y" && axis != "z") below.fail(below.node("axis"), "must be x, y or z", "axis");
    fixed.axis = axis[0] - 'x';
    fixed.value = units * below.number("value", 0.0);
    below.finish();
  }
  reader.finish();
  return fixed;
}

Procedural readProcedural(MapReader reader) {
  Procedural p;
  const std::string shape = reader.text("shape", "");
  if (shape == "slab") {
    p.shape = Procedural::Shape::Slab;
  } else if (shape == "pillow") {
    p.shape = Procedural::Shape::Pillow;
    p.coarseCells = {10, 8, 2};
    p.fineCells = {24, 20, 4};
  } else if (shape == "meniscus") {
    p.shape = Procedural::Shape::Meniscus;
    p.coarseCells = {3, 10, 2};
    p.fineCells = {6, 24, 3};
  } else {
    reader.fail(reader.node("shape"), "must be slab, pillow or meniscus", "shape");
  }
  constexpr int kMostCells = 1000;  // per axis: 1e9 cells is far past what a scene can solve
  const auto cells = [&](const char* key, Eigen::Vector3i& value) {
    if (!reader.has(key)) return;
    const std::vector<double> c = reader.numbers(key, 3);
    for (int k = 0; k < 3; ++k) {
      if (!(c[k] >= 1 && c[k] <= kMostCells) || c[k] != std::floor(c[k]))
        reader.fail(reader.node(key), "must hold integers in [1, " + std::to_string(kMostCells) + "]", key);
      value[k] = static_cast<int>(c[k]);
    }
  };
  cells("coarse_cells", p.coarseCells);
  cells("fine_cells", p.fineCells);
  p.coarseSkinLayers = reader.integer("coarse_skin_layers", p.coarseSkinLayers, 1);
  p.fineSkinLayers = reader.integer("fine_skin_layers", p.fineSkinLayers, 1);
  reader.finish();
  return p;
}

// The nested {key: value} maps with positive numbers only (coarse, fine, tool, stamp, descriptors).
template <class Body>
void readSection(MapReader& scene, const std::string& key, const Body& body) {
  if (!scene.has(key)) return;
  MapReader section = scene.map(key);
  body(section);
  section.finish();
}

// The scene of a parsed YAML document. `path` names it in messages; files are resolved against `folder`
// and must exist when `requireFiles` (a scene file), or are kept as written (a set's provenance).
SceneDescription parseScene(const YAML::Node& root, const std::string& path, const fs::path& folder, bool requireFiles) {
  MapReader scene(root, path, "");
  const auto file = [&](const std::string& key) {
    return requireFiles ? existingFile(scene, key, folder, path) : scene.text(key, "");
  };
  SceneDescription d;
  d.path = requireFiles ? fs::absolute(path).lexically_normal().string() : path;
  d.name = scene.text("name", fs::path(path).stem().string());
  d.units = scene.positive("units", 1.0);
  if (scene.has("procedural")) {
    if (scene.has("surface") || scene.has("volume")) scene.failHere("a procedural scene names no 'surface' or 'volume'");
    d.procedural = readProcedural(scene.map("procedural"));
  } else {
    if (!scene.has("surface")) scene.failHere("needs 'surface' (the display surface file) or 'procedural'");
    d.surface = file("surface");
    if (scene.has("volume")) d.volume = file("volume");
  }
  readSection(scene, "coarse", [&](MapReader& s) { d.coarseMaxVolume = s.positive("max_volume", 0.0); });
  readSection(scene, "fine", [&](MapReader& s) { d.fineMaxVolume = s.positive("max_volume", 0.0); });
  if (!d.procedural && d.volume.empty() && d.coarseMaxVolume == 0.0)
    scene.failHere("needs 'volume' or 'coarse: {max_volume: ...}' to make a coarse tet mesh");
  if (!scene.has("material")) scene.failHere("needs 'material: {young: ..., poisson: ...}'");
  d.material = readMaterial(scene.map("material"));
  if (scene.has("skin")) {
    MapReader skin = scene.map("skin");
    Skin s;
    s.thickness = skin.positive("thickness", 0.0);
    s.material.young = skin.positive("young", 0.0);
    s.material.poisson = skin.number("poisson", 0.3);
    if (!(s.material.poisson > -1.0 && s.material.poisson < 0.5))
      skin.fail(skin.node("poisson"), "must lie in (-1, 0.5)", "poisson");
    if (skin.has("coarse_young")) d.coarseSkinYoung = skin.positive("coarse_young", 0.0);
    skin.finish();
    d.skin = s;
  }
  if (scene.has("fixed")) {
    d.fixed = readFixed(scene.map("fixed"), d.units);
  } else if (!d.procedural) {
    scene.failHere("needs 'fixed' (vertices, box or below): where the object is held");
  }
  readSection(scene, "tool", [&](MapReader& s) {
    const std::string model = s.text("model", "penalty");
    if (model != "penalty" && model != "dirichlet") s.fail(s.node("model"), "must be penalty or dirichlet", "model");
    d.tool.model = model == "penalty" ? ToolModel::Penalty : ToolModel::Dirichlet;
    d.tool.radius = s.positive("radius", d.tool.radius);
    d.tool.stiffness = s.positive("stiffness", d.tool.stiffness);
  });
  readSection(scene, "solve", [&](MapReader& s) {
    d.solve.indentSteps = s.integer("indent_steps", d.solve.indentSteps, 1);
    d.solve.dragSteps = s.integer("drag_steps", d.solve.dragSteps, 0);
    d.solve.relativeTolerance = s.positive("relative_tolerance", d.solve.relativeTolerance);
  });
  readSection(scene, "stamp", [&](MapReader& s) {
    d.stamp.radius = s.positive("radius", d.stamp.radius);
    d.stamp.resolution = s.integer("resolution", d.stamp.resolution, 2);
    d.stamp.layers = s.integer("layers", d.stamp.layers, 1);
  });
  readSection(scene, "descriptors", [&](MapReader& s) {
    d.descriptors.windowScale = s.positive("window_scale", d.descriptors.windowScale);
    d.descriptors.cutoff = s.positive("cutoff", d.descriptors.cutoff);
    d.descriptors.sampleSpacing = s.positive("sample_spacing", d.descriptors.sampleSpacing);
    const std::string quadrature = s.text("quadrature", "volume");
    if (quadrature != "volume" && quadrature != "average") s.fail(s.node("quadrature"), "must be volume or average", "quadrature");
    d.descriptors.averageQuadrature = quadrature == "average";
  });
  d.maxOutside = scene.positive("max_outside", d.maxOutside);
  const std::string plan = scene.text("plan", "auto");
  d.plan = plan == "auto" ? plan : file("plan");
  scene.finish();
  return d;
}

YAML::Node loadYaml(const std::string& text, const std::string& name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw IoError(name + ":" + std::to_string(e.mark.line + 1) + ": not a valid YAML scene: " + e.msg);
  }
}

}  // namespace

SceneDescription readSceneFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseScene(loadYaml(text.str(), path), path, fs::absolute(path).parent_path(), true);
}

SceneDescription parseSceneText(const std::string& text, const std::string& name) {
  return parseScene(loadYaml(text, name), name, fs::path(), false);
}

std::vector<std::string> shippedScenes() {
  std::set<std::string> names;
  for (const fs::path& dir : {fs::path(DE_GENERATED_SCENE_DIR), fs::path(DE_INSTALL_SCENE_DIR), fs::path(DE_SOURCE_SCENE_DIR)}) {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(dir, error))
      if (entry.path().extension() == ".yaml") names.insert(entry.path().stem().string());
  }
  return {names.begin(), names.end()};
}

std::string findSceneFile(const std::string& nameOrPath) {
  const fs::path given(nameOrPath);
  if (given.extension() == ".yaml" || given.extension() == ".yml" || nameOrPath.find('/') != std::string::npos) {
    if (!fs::is_regular_file(given)) throw IoError(nameOrPath + ": no such scene file");
    return fs::absolute(given).lexically_normal().string();
  }
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("DE_SCENE_DIR"); env && *env) dirs.emplace_back(env);
  dirs.emplace_back(DE_GENERATED_SCENE_DIR);
  dirs.emplace_back(DE_INSTALL_SCENE_DIR);
  dirs.emplace_back(DE_SOURCE_SCENE_DIR);
  for (const fs::path& dir : dirs)
    if (fs::is_regular_file(dir / (nameOrPath + ".yaml"))) return (dir / (nameOrPath + ".yaml")).string();
  std::string known;
  for (const std::string& name : shippedScenes()) known += (known.empty() ? "" : ", ") + name;
  throw IoError("no scene named '" + nameOrPath + "' (shipped scenes: " + known + "; or give a path to a .yaml file)");
}

}  // namespace deformation_enrichment::scene_file
