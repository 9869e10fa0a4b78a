#pragma once
// A scene file (YAML) describes one object for acquisition, evaluation, the demo and the node: its display
// surface, its coarse tet mesh (or how to make one), materials, the fixed region, the tool, the stamps and
// the acquisition plan (docs/design.md §6; format in docs/scenes.md). Built-in scenes are files shipped in
// config/scenes/; a procedural scene (slab, pillow, meniscus) names its shape instead of mesh files.
// Lengths are metres after `units` is applied (file units only inside mesh files and `fixed`).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace deformation_enrichment::scene_file {

struct Material {
  double young = 0.0;    ///< Young's modulus (Pa), > 0
  double poisson = 0.0;  ///< Poisson ratio in (-1, 0.5)
};

/// A stiff layer under the surface: tets whose centroid lies within `thickness` of the display surface.
struct Skin {
  double thickness = 0.0;  ///< m, > 0
  Material material;
};

/// Where the object is held (Dirichlet, at rest).
struct FixedRegion {
  enum class Kind { Vertices, Box, Below };
  Kind kind = Kind::Below;
  std::vector<int> vertices;                        ///< Vertices: 0-based coarse volume node ids, file order
  Eigen::Vector3d boxLo = Eigen::Vector3d::Zero();  ///< Box: corners (m)
  Eigen::Vector3d boxHi = Eigen::Vector3d::Zero();
  int axis = 2;                                     ///< Below: 0, 1, 2 for x, y, z
  double value = 0.0;                               ///< Below: coordinate (m); nodes at or below it are fixed
};

/// How the tool loads the tissue. Penalty springs are smooth in the tool position, so fine - coarse varies
/// smoothly between contacts; Dirichlet grabs whole vertices under the tip and makes it jump with the mesh
/// (held-out slab ratio 1.04 against 0.53 with the penalty tool, docs/design.md §7).
enum class ToolModel { Penalty, Dirichlet };

struct Tool {
  ToolModel model = ToolModel::Penalty;
  double radius = 0.005;     ///< footprint radius (m)
  double stiffness = 1.0e9;  ///< penalty stiffness per area (Pa/m)
};

/// The quasi-static path of one interaction: indent in `indentSteps`, then drag in `dragSteps`.
struct Solve {
  int indentSteps = 2, dragSteps = 2;
  double relativeTolerance = 1e-7;  ///< Newton stop: |residual| <= this * |first residual|
};

struct StampGrid {
  double radius = 0.03;  ///< R (m)
  int resolution = 32;   ///< nodes per side
  int layers = 9;        ///< volume stamp layers along b_z (enrichment/stamp.hpp); 1: the paper's surface stamp
};

/// Descriptor options of the examples (and so of the run time, which takes them from the set).
struct Descriptors {
  double windowScale = 0.006;   ///< Hermite window scale h (m)
  double cutoff = 4.0;          ///< window cut-off in units of h
  double sampleSpacing = 0.002; ///< interior sampling of the site density (m)
  bool averageQuadrature = false;  ///< [Seiler14 eq. 8]'s point average instead of volume weights
};

/// A built-in procedural object instead of mesh files (the coarse and fine models are layered grids).
struct Procedural {
  enum class Shape { Slab, Pillow, Meniscus };
  Shape shape = Shape::Slab;
  Eigen::Vector3i coarseCells{10, 10, 2};  ///< (first, second surface direction, bulk layers)
  Eigen::Vector3i fineCells{24, 24, 4};
  int coarseSkinLayers = 1, fineSkinLayers = 2;
};

struct SceneDescription {
  std::string name;
  std::string path;   ///< the scene file (absolute)
  double units = 1.0; ///< metres per file unit of the mesh files and of `fixed`
  std::string surface;  ///< display surface file (absolute); empty for a procedural scene
  std::string volume;   ///< coarse tet mesh file (absolute); empty: tetrahedralise the closed surface
  double coarseMaxVolume = 0.0;  ///< m^3, coarse tets when `volume` is empty
  double fineMaxVolume = 0.0;    ///< m^3, the fine model's largest tet; 0: scenes::defaultFineMaxVolume of the surface
  std::optional<Procedural> procedural;
  Material material;
  std::optional<Skin> skin;
  /// Coarse model's skin modulus (Pa); empty: the skin's (the slab's coarse skin can differ).
  std::optional<double> coarseSkinYoung;
  /// Required for mesh files (an unheld body has no quasi-static solution); a procedural scene without it
  /// keeps its shape's support (slab and pillow: the bottom; meniscus: bottom and outer rim).
  std::optional<FixedRegion> fixed;
  Tool tool;
  Solve solve;
  StampGrid stamp;
  Descriptors descriptors;
  std::string plan = "auto";  ///< "auto", or a CSV file (absolute)
  double maxOutside = 0.002;  ///< m: display vertices farther outside the coarse volume are refused
};

/// Reads and validates a scene file. Relative paths are relative to the file. Throws IoError naming the
/// file (and line) for an unreadable or malformed file or a missing mesh/plan file, and InvalidInputError
/// naming the file, the line and the key for an unknown key, a wrong type or a value out of range (units
/// <= 0, Poisson ratio outside (-1, 0.5), non-positive moduli, lengths or volumes, a malformed fixed region).
SceneDescription readSceneFile(const std::string& path);

/// A scene from YAML text (a set's provenance): validated like a file, but file names are kept as written
/// and need not exist. `name` stands for the text in messages.
SceneDescription parseSceneText(const std::string& text, const std::string& name);

/// The scene as YAML with every key explicit and files by their names only (no folders): what a set's
/// provenance records. parseSceneText(sceneYaml(s)) gives s back (paths as names).
std::string sceneYaml(const SceneDescription& scene);

/// `nameOrPath` as a scene file: a path ending in .yaml/.yml, or the name of a shipped scene
/// (config/scenes/<name>.yaml, found in $DE_SCENE_DIR, then among the scenes the build generates (the
/// liver), then the installed share folder, then the source tree). Throws IoError listing the shipped scenes when there is no such file.
std::string findSceneFile(const std::string& nameOrPath);

/// Names of the shipped scenes (sorted).
std::vector<std::string> shippedScenes();

}  // namespace deformation_enrichment::scene_file
