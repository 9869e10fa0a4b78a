#pragma once
// Plan / contacts CSV of the acquisition tools (de_make_examples --plan, de_evaluate --contacts): one
// interaction per line, `x,y,z,depth,dx,dy,dz` (metres), blank lines and lines starting with '#' skipped.
#include <Eigen/Core>
#include <iosfwd>
#include <string>
#include <vector>

namespace deformation_enrichment::acquisition {

/// One line of a plan / contacts CSV: contact near the rest surface, indentation depth along the inward
/// normal, lateral drag vector.
struct PlanEntry {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double depth = 0.0;
  Eigen::Vector3d drag = Eigen::Vector3d::Zero();
};

/// Parses the CSV. Throws IoError naming the file and line for an unreadable file, a wrong field count, a
/// non-numeric or non-finite field, a negative depth, or no entry at all.
std::vector<PlanEntry> readPlan(const std::string& path);
/// The same from a stream; `name` stands for the file in error messages.
std::vector<PlanEntry> readPlan(std::istream& in, const std::string& name);

/// Writes the CSV with every value round-tripping exactly; the path version throws IoError naming the file.
void writePlan(std::ostream& out, const std::vector<PlanEntry>& plan);
void writePlan(const std::string& path, const std::vector<PlanEntry>& plan);

}  // namespace deformation_enrichment::acquisition
