#include "deformation_enrichment/mesh/connected_components.hpp"

#include <string>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/connected_components.hpp>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

std::vector<std::vector<int>> connectedComponents(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices) {
  boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS> graph(static_cast<size_t>(numVertices));
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (triangles(k, t) < 0 || triangles(k, t) >= numVertices)
        throw InvalidInputError("connected components: triangle " + std::to_string(t) + " has vertex index " +
                                std::to_string(triangles(k, t)) + " outside [0, " + std::to_string(numVertices) + ")");
    }
    boost::add_edge(static_cast<size_t>(triangles(0, t)), static_cast<size_t>(triangles(1, t)), graph);
    boost::add_edge(static_cast<size_t>(triangles(1, t)), static_cast<size_t>(triangles(2, t)), graph);
  }
  std::vector<int> label(static_cast<size_t>(numVertices));
  const int count = boost::connected_components(graph, label.data());  // labels in order of first vertex
  std::vector<std::vector<int>> components(static_cast<size_t>(count));
  for (size_t v = 0; v < label.size(); ++v) components[static_cast<size_t>(label[v])].push_back(static_cast<int>(v));
  return components;
}

}  // namespace deformation_enrichment::mesh
