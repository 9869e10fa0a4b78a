#include "deformation_enrichment/acquisition/plan_io.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/number_parsing.hpp"

namespace deformation_enrichment::acquisition {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

}  // namespace

std::vector<PlanEntry> readPlan(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open plan");
  return readPlan(in, path);
}

std::vector<PlanEntry> readPlan(std::istream& in, const std::string& name) {
  std::vector<PlanEntry> plan;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::string where = name + ":" + std::to_string(number) + ": ";
    std::vector<double> v;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) {
      field = trim(field);
      const std::optional<double> value = parseReal(field);
      if (!value) throw IoError(where + "'" + field + "' is not a number");
      if (!std::isfinite(*value)) throw IoError(where + "non-finite value");
      v.push_back(*value);
    }
    if (v.size() != 7) throw IoError(where + "expected 7 fields x,y,z,depth,dx,dy,dz, got " + std::to_string(v.size()));
    if (v[3] < 0.0) throw IoError(where + "negative indentation depth");
    PlanEntry e;
    e.point = Eigen::Vector3d(v[0], v[1], v[2]);
    e.depth = v[3];
    e.drag = Eigen::Vector3d(v[4], v[5], v[6]);
    plan.push_back(e);
  }
  if (plan.empty()) throw IoError(name + ": no interaction in the plan");
  return plan;
}

void writePlan(std::ostream& out, const std::vector<PlanEntry>& plan) {
  out << "# x,y,z,depth,dx,dy,dz (m)\n" << std::setprecision(17);  // round-trips every double
  for (const PlanEntry& e : plan)
    out << e.point.x() << ',' << e.point.y() << ',' << e.point.z() << ',' << e.depth << ',' << e.drag.x() << ','
        << e.drag.y() << ',' << e.drag.z() << '\n';
}

void writePlan(const std::string& path, const std::vector<PlanEntry>& plan) {
  std::ostringstream text;
  writePlan(text, plan);
  writeFileAtomically(path, text.str());
}

}  // namespace deformation_enrichment::acquisition
