#pragma once
// The run-time benchmarks' scene: a ~50k-vertex slab surface (150 x 150 x 3 cells), the default slab scene's
// descriptor options, 10 examples described on it with random 32 x 32 surface stamps (a set that records the
// slab scene, as acquired sets do), and a dented, dragged current state under a contact. slabBenchSet gives
// larger sets with the scene's volume stamps (stamp.layers) for the cost of the number of examples.
#include <opencv2/core.hpp>

#include <cmath>
#include <memory>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace de_bench {

namespace de = deformation_enrichment;

// A smooth dent of `depth` under p (stands in for the coarse state; its shape only sets mu).
inline Eigen::Matrix3Xd dented(const Eigen::Matrix3Xd& rest, const Eigen::Vector3d& p, double depth, const Eigen::Vector3d& drag) {
  Eigen::Matrix3Xd x = rest;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    const double w = std::exp(-(rest.col(v) - p).squaredNorm() / (2 * 0.006 * 0.006)) * rest(2, v) / 0.02;
    x.col(v) += w * (drag - depth * Eigen::Vector3d::UnitZ());
  }
  return x;
}

/// The slab's tet mesh with `cells` x `cells` x `layers` cells.
inline de::mesh::TetMesh slabVolume(int cells, int layers = 3) {
  return de::mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(cells, cells, layers));
}

/// The slab's surface with `cells` x `cells` x `layers` cells (150 x 150 x 3: 45 904 top and ~50k surface
/// vertices; 700 x 700 x 1: ~1M).
inline de::mesh::TriangleMesh slabSurface(int cells, int layers = 3) {
  return de::mesh::extractSurface(slabVolume(cells, layers)).surface;
}

struct SlabBenchScene {
  de::mesh::TriangleMesh surface;
  de::enrichment::ContactEnricherOptions options;
  de::examples::ExampleSet set;
  Eigen::Matrix3Xd current;
  Eigen::Vector3d contact;
};

/// `count` examples described on `surface` at contacts spread over the slab's top, depths 2-4.5 mm and small
/// drags, with random stamps of `layers` layers of 32 x 32 nodes.
inline de::examples::ExampleSet slabBenchSet(const de::mesh::TriangleMesh& surface, const de::enrichment::ContactEnricherOptions& options,
                                             const de::scene_file::SceneDescription& slab, int count, int layers) {
  de::enrichment::ContactEnricher describer(surface, options);
  de::examples::ExampleSet set;
  set.metadata.provenance = de::examples::Provenance{slab, {}, {}};
  cv::RNG rng(1);
  for (int i = 0; i < count; ++i) {
    de::enrichment::Contact c;
    c.point = Eigen::Vector3d(-0.02 + 0.004 * (i % 10) + 0.0004 * (i / 10), 0.01 * std::sin(i), 0.02);
    const Eigen::Vector3d drag(0.0005 * (i % 3), 0.0005 * (i % 2), 0.0);
    const de::enrichment::ContactDescription d = describer.describe(dented(surface.vertices, c.point, 0.002 + 0.0002 * (i % 13), drag), c);
    de::examples::Example e;
    e.contact = d.p;
    e.frame = d.B;
    e.rho = d.rho;
    e.mu = d.mu;
    e.stampRadius = options.stampRadius;
    e.stampLayers = layers;
    e.stamp.create(32 * layers, 32, CV_32FC3);
    rng.fill(e.stamp, cv::RNG::NORMAL, cv::Scalar::all(0.0), cv::Scalar::all(1e-4));
    set.examples.push_back(e);
  }
  return set;
}

inline const SlabBenchScene& slabBenchScene() {
  static std::unique_ptr<SlabBenchScene> s;
  if (s) return *s;
  s = std::make_unique<SlabBenchScene>();
  s->surface = slabSurface(150);
  const de::scene_file::SceneDescription slab = de::scene_file::readSceneFile(de::scene_file::findSceneFile("slab"));
  s->options = de::enrichment::optionsFor(slab);
  s->set = slabBenchSet(s->surface, s->options, slab, 10, 1);
  s->contact = Eigen::Vector3d(0.003, -0.002, 0.02);
  s->current = dented(s->surface.vertices, s->contact, 0.0025, Eigen::Vector3d(0.0004, 0.0, 0.0));
  return *s;
}

}  // namespace de_bench
