#pragma once
// Connected components of a triangle mesh (vertices joined by triangle edges), e.g. the separate pieces of
// an MD2 model (faerie.md2 has 13: a body and 12 small parts). Each piece moves rigidly at no cost to an
// elastic energy of the whole mesh, so the shape-space flow keeps every piece's pose.
#include <vector>

#include <Eigen/Core>

namespace deformation_enrichment::mesh {

/// The vertex lists of the components of the graph whose edges are the triangles' edges, in the order of
/// their smallest vertex; vertices no triangle uses form components of their own. Throws InvalidInputError
/// for indices outside [0, numVertices).
std::vector<std::vector<int>> connectedComponents(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices);

}  // namespace deformation_enrichment::mesh
