// de_descriptors: site descriptor rho, stamping frame B and (with --deformed) the deformation descriptor mu
// of [Seiler14 §4] at given points of an object, for choosing acquisition points and for scripts.
//
//   de_descriptors --mesh M.node --points P.csv --order N --scale h --quadrature volume|average
//                  [--cutoff c] [--deformed D.node] --json
//
// M.node has M.ele beside it (TetGen); a closed OBJ/PLY surface is accepted too and sampled on an interior
// grid (spacing --sample-spacing, default h/4; site descriptors only). P.csv: one "x,y,z" per line.
// D.node: displaced positions of the same vertices. All moments are printed in world axes, each order as
// its distinct components in lexicographic multi-index order (n=1: x y z; n=2: xx xy xz yy yz zz; ...),
// each the tensor component itself (not multiplied by its multiplicity). mu holds, per order, three lists:
// the moments of the x, y and z components of the rigid-free displacement (eq. 10). Beyond the issue's
// layout each point carries "frame_rule" (which rule fixed b_x) and, if it failed, "error" (exit code 1).
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "deformation_enrichment/descriptors/evaluator_loading.hpp"
#include "deformation_enrichment/error.hpp"
#include "descriptor_cli.hpp"
#include "command_line.hpp"

using namespace deformation_enrichment;
using Json = nlohmann::ordered_json;

namespace {

std::vector<Eigen::Vector3d> readPoints(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError("cannot open points file " + path);
  std::vector<Eigen::Vector3d> points;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    for (char& c : line)
      if (c == ',' || c == ';') c = ' ';
    std::istringstream fields(line);
    Eigen::Vector3d p;
    std::string rest;
    if (!(fields >> p.x() >> p.y() >> p.z()) || (fields >> rest))
      throw IoError(path + ":" + std::to_string(number) + ": expected 'x,y,z'");
    if (!p.allFinite()) throw IoError(path + ":" + std::to_string(number) + ": point is not finite");
    points.push_back(p);
  }
  if (points.empty()) throw IoError(path + ": no points");
  return points;
}

// Positions of a TetGen .node file (header "count 3 attributes markers", then "index x y z ...").
Eigen::Matrix3Xd readNodePositions(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError("cannot open node file " + path);
  std::vector<std::vector<std::string>> records;
  std::string line;
  while (std::getline(in, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream tokens(line);
    std::vector<std::string> fields;
    for (std::string token; tokens >> token;) fields.push_back(token);
    if (!fields.empty()) records.push_back(fields);
  }
  if (records.empty()) throw IoError(path + ": empty node file");
  const long count = std::stol(records[0][0]);
  if (count <= 0 || static_cast<long>(records.size()) < count + 1)
    throw IoError(path + ": header announces " + std::to_string(count) + " points, file has " +
                  std::to_string(records.size() - 1));
  Eigen::Matrix3Xd positions(3, count);
  for (long i = 0; i < count; ++i) {
    const auto& fields = records[i + 1];
    if (fields.size() < 4) throw IoError(path + ": point " + std::to_string(i) + " has fewer than 4 fields");
    for (int k = 0; k < 3; ++k) {
      std::size_t used = 0;
      positions(k, i) = std::stod(fields[1 + k], &used);
      if (used != fields[1 + k].size() || !std::isfinite(positions(k, i)))
        throw IoError(path + ": point " + std::to_string(i) + " has a bad coordinate '" + fields[1 + k] + "'");
    }
  }
  return positions;
}

Json vectorJson(const Eigen::Ref<const Eigen::VectorXd>& v) {
  Json array = Json::array();
  for (Eigen::Index k = 0; k < v.size(); ++k) array.push_back(v[k]);
  return array;
}

Json matrixJson(const Eigen::Matrix3d& m) {  // column-major, as the issue specifies
  return vectorJson(Eigen::Map<const Eigen::VectorXd>(m.data(), 9));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Site / deformation descriptors ([Seiler14 §4]) at given points, in world axes"};
  tools::DescriptorCli cli;
  std::string pointsPath, deformedPath;
  int deformationOrder = 2;
  bool json = false;
  cli.addTo(app);
  app.add_option("--points", pointsPath, "CSV file, one x,y,z per line")->required();
  app.add_option("--deformation-order", deformationOrder, "deformation descriptor order (1..4)")->capture_default_str();
  app.add_option("--deformed", deformedPath, "D.node with displaced positions of the same vertices");
  app.add_flag("--json", json, "print one JSON object (otherwise a short text summary)");
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;

  try {
    descriptors::DescriptorOptions options;
    options.deformationOrder = deformationOrder;
    const descriptors::LoadedObject object = cli.load(options);
    const std::vector<Eigen::Vector3d> points = readPoints(pointsPath);
    Eigen::Matrix3Xd deformed;
    if (!deformedPath.empty()) {
      if (!object.volumetric) throw InvalidInputError("--deformed needs a tet mesh (.node), not a surface");
      deformed = readNodePositions(deformedPath);
      if (deformed.cols() != object.evaluator.sampling().size())
        throw InvalidInputError(deformedPath + " has " + std::to_string(deformed.cols()) + " points, the mesh has " +
                                std::to_string(object.evaluator.sampling().size()));
    }

    // The issue's layout is {"points": [...]}; how the samples were made goes to stderr.
    std::cerr << "de_descriptors: samples: " << object.sampling << '\n';
    Json output;
    output["points"] = Json::array();
    int failures = 0;
    for (const Eigen::Vector3d& p : points) {
      Json entry;
      entry["p"] = vectorJson(p);
      try {
        const descriptors::ContactDescriptor contact =
            deformed.cols() > 0 ? object.evaluator.evaluate(p, deformed) : object.evaluator.evaluate(p);
        Json site;
        for (int n = 0; n <= cli.order; ++n) site[std::to_string(n)] = vectorJson(contact.rhoWorld.order(n));
        entry["site"] = site;
        entry["frame"] = matrixJson(contact.frame.B);
        entry["frame_rule"] = descriptors::toString(contact.frame.rule);
        if (contact.deformation) {
          Json mu;
          for (int n = 1; n <= deformationOrder; ++n) {
            Json components = Json::array();
            for (int c = 0; c < 3; ++c) components.push_back(vectorJson(contact.deformation->mu.order(n, c)));
            mu[std::to_string(n)] = components;
          }
          entry["deformation"] = {{"F", matrixJson(contact.deformation->F)},
                                  {"R", matrixJson(contact.deformation->R)},
                                  {"mu", mu}};
        }
      } catch (const Error& error) {
        entry["error"] = error.what();
        ++failures;
      }
      output["points"].push_back(entry);
    }
    if (json) {
      std::cout << output.dump(2) << '\n';
    } else {
      for (const Json& entry : output["points"]) {
        std::cout << "p = " << entry["p"].dump();
        if (entry.contains("error")) std::cout << "  error: " << entry["error"].get<std::string>() << '\n';
        else std::cout << "  rho_0 = " << entry["site"]["0"][0].get<double>() << "  frame rule "
                       << entry["frame_rule"].get<std::string>() << '\n';
      }
    }
    return failures == 0 ? 0 : 1;
  } catch (const Error& error) {
    std::cerr << "de_descriptors: " << error.what() << '\n';
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "de_descriptors: " << error.what() << '\n';
    return 2;
  }
}
