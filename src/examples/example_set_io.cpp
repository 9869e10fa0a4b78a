#include "deformation_enrichment/examples/example_set_io.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::examples {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The blob is defined as little-endian float32; reject big-endian hosts instead of writing wrong bytes.
bool hostIsLittleEndian() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

std::string hex64(std::uint64_t v) {
  std::ostringstream s;
  s << std::hex << std::setw(16) << std::setfill('0') << v;
  return s.str();
}

json momentsToJson(const hermite::MomentList& m) {
  return json{{"first_order", m.firstOrder()}, {"last_order", m.lastOrder()}, {"channels", m.channels()},
              {"values", std::vector<double>(m.values().data(), m.values().data() + m.values().size())}};
}

// Manifest reading: every accessor names the field path so the error says exactly what is wrong.
class ManifestReader {
public:
  explicit ManifestReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& problem) const { throw IoError(file_ + ": " + problem); }

  const json& field(const json& obj, const std::string& key, const std::string& path) const {
    if (!obj.is_object()) fail(path + " is not an object");
    const auto it = obj.find(key);
    if (it == obj.end()) fail("missing field " + path + "." + key);
    return *it;
  }
  double number(const json& obj, const std::string& key, const std::string& path) const {
    const json& v = field(obj, key, path);
    if (!v.is_number()) fail("field " + path + "." + key + " is not a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail("field " + path + "." + key + " is not finite");
    return d;
  }
  int integer(const json& obj, const std::string& key, const std::string& path) const {
    const json& v = field(obj, key, path);
    if (!v.is_number_integer()) fail("field " + path + "." + key + " is not an integer");
    // get<int>() would wrap: format_version 4294967297 read as 1, stamp_rows 4294967298 as 2.
    const bool fits = v.is_number_unsigned() ? v.get<std::uint64_t>() <= std::uint64_t(std::numeric_limits<int>::max())
                                             : v.get<std::int64_t>() >= std::numeric_limits<int>::min() &&
                                                   v.get<std::int64_t>() <= std::numeric_limits<int>::max();
    if (!fits) fail("field " + path + "." + key + " is outside the int range");
    return v.get<int>();
  }
  std::string string(const json& obj, const std::string& key, const std::string& path) const {
    const json& v = field(obj, key, path);
    if (!v.is_string()) fail("field " + path + "." + key + " is not a string");
    return v.get<std::string>();
  }
  std::vector<double> numbers(const json& v, const std::string& path, std::size_t expected) const {
    if (!v.is_array()) fail("field " + path + " is not an array");
    if (expected != 0 && v.size() != expected)
      fail("field " + path + " has " + std::to_string(v.size()) + " entries, expected " + std::to_string(expected));
    std::vector<double> out;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_number()) fail("field " + path + "[" + std::to_string(i) + "] is not a number (NaN is stored as null)");
      out.push_back(v[i].get<double>());
      if (!std::isfinite(out.back())) fail("field " + path + "[" + std::to_string(i) + "] is not finite");
    }
    return out;
  }
  hermite::MomentList moments(const json& obj, const std::string& key, const std::string& path) const {
    const json& m = field(obj, key, path);
    const std::string p = path + "." + key;
    const int first = integer(m, "first_order", p);
    const int last = integer(m, "last_order", p);
    const int channels = integer(m, "channels", p);
    hermite::MomentList list;
    try {
      list = hermite::MomentList(first, last, channels);
    } catch (const Error& e) {
      fail("field " + p + " has an invalid layout: " + e.what());
    }
    const std::vector<double> values = numbers(field(m, "values", p), p + ".values", 0);
    if (values.size() != static_cast<std::size_t>(list.values().size()))
      fail("field " + p + ".values has " + std::to_string(values.size()) + " entries, orders " + std::to_string(first) +
           ".." + std::to_string(last) + " with " + std::to_string(channels) + " channel(s) need " +
           std::to_string(list.values().size()));
    for (std::size_t i = 0; i < values.size(); ++i) list.values()[static_cast<Eigen::Index>(i)] = values[i];
    return list;
  }

private:
  std::string file_;
};

bool sameLayout(const hermite::MomentList& a, const hermite::MomentList& b) {
  return a.firstOrder() == b.firstOrder() && a.lastOrder() == b.lastOrder() && a.channels() == b.channels();
}

// coarse_simulator only when another simulator made the coarse half, so the package's own sets read as before.
json provenanceJson(const Provenance& p) {
  json out{{"scene", scene_file::sceneYaml(p.scene)}, {"file_hashes", p.fileHashes}};
  if (!p.coarseSimulator.empty()) out["coarse_simulator"] = p.coarseSimulator;
  return out;
}

}  // namespace

std::uint64_t fnv1a64(const void* data, std::size_t size) {
  // FNV-1a 64: offset basis and prime from the FNV specification.
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

void saveExampleSet(const ExampleSet& set, const std::string& directory) {
  if (!hostIsLittleEndian()) throw IoError(directory + ": example sets are little-endian; big-endian hosts are not supported");
  if (set.examples.empty()) throw InvalidInputError("saveExampleSet: the set has no examples");
  for (std::size_t i = 0; i < set.examples.size(); ++i) {
    const Example& e = set.examples[i];
    validateExample(e, "example " + std::to_string(i));
    if (e.stamp.size() != set.examples[0].stamp.size() || e.stampLayers != set.examples[0].stampLayers ||
        std::abs(e.stampRadius - set.examples[0].stampRadius) > 1e-9 * set.examples[0].stampRadius)
      throw InvalidInputError("saveExampleSet: example " + std::to_string(i) + " stamp size or radius differs from example 0");
  }

  std::vector<char> blob;
  json examples = json::array();
  for (const Example& e : set.examples) {
    const cv::Mat stamp = e.stamp.isContinuous() ? e.stamp : e.stamp.clone();
    const std::size_t offset = blob.size();
    const std::size_t bytes = stamp.total() * stamp.elemSize();
    blob.resize(offset + bytes);
    std::memcpy(blob.data() + offset, stamp.ptr(), bytes);
    json frame = json::array();
    for (int r = 0; r < 3; ++r) frame.push_back({e.frame(r, 0), e.frame(r, 1), e.frame(r, 2)});
    examples.push_back({{"contact", {e.contact.x(), e.contact.y(), e.contact.z()}},
                        {"frame_rows", frame},
                        {"rho", momentsToJson(e.rho)},
                        {"mu", momentsToJson(e.mu)},
                        {"stamp_radius", e.stampRadius},
                        {"stamp_rows", stamp.rows},
                        {"stamp_cols", stamp.cols},
                        {"stamp_layers", e.stampLayers},
                        {"stamp_offset_bytes", offset},
                        {"pattern", {{"indent_depth", e.pattern.indentDepth},
                                     {"drag", {e.pattern.drag.x(), e.pattern.drag.y(), e.pattern.drag.z()}}}},
                        {"scene_id", e.sceneId},
                        {"plan_line", e.planLine}});
  }
  json material = json::object();
  for (const auto& [name, value] : set.metadata.material) {
    if (!std::isfinite(value)) throw InvalidInputError("saveExampleSet: material parameter " + name + " is not finite");
    material[name] = value;
  }
  const json manifest = {
      {"format", kExampleSetFormatName},
      {"format_version", kExampleSetFormatVersion},
      {"package_version", kPackageVersion},
      {"units", {{"length", "m"}, {"stamp_displacement", "m"}}},
      {"scene", set.metadata.scene},
      {"material", material},
      {"description", set.metadata.description},
      {"provenance", set.metadata.provenance ? provenanceJson(*set.metadata.provenance) : json(nullptr)},
      {"stamp_blob", {{"file", kStampBlobFile},
                      {"dtype", "float32_le"},
                      {"layout", "rows x cols x 3, row-major, examples in manifest order"},
                      {"size_bytes", blob.size()},
                      {"fnv1a64", hex64(fnv1a64(blob.data(), blob.size()))}}},
      {"examples", examples}};

  const fs::path dir(directory);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(directory + ": cannot create directory: " + ec.message());
  // Blob first, manifest last: a manifest under its final name always describes a complete blob.
  writeFileAtomically(dir / kStampBlobFile, std::string_view(blob.data(), blob.size()));
  const std::string text = manifest.dump(1);
  writeFileAtomically(dir / kManifestFile, text);
}

namespace {

// The manifest's header: format, version, units and set metadata.
void readHeader(const ManifestReader& r, const json& manifest, ExampleSetMetadata& metadata) {
  if (r.string(manifest, "format", "manifest") != kExampleSetFormatName) r.fail("format is not " + std::string(kExampleSetFormatName));
  const int version = r.integer(manifest, "format_version", "manifest");
  if (version != kExampleSetFormatVersion)
    r.fail("unsupported format_version " + std::to_string(version) + " (this build reads " +
           std::to_string(kExampleSetFormatVersion) + ")");
  r.string(manifest, "package_version", "manifest");
  const json& units = r.field(manifest, "units", "manifest");
  if (r.string(units, "length", "manifest.units") != "m") r.fail("units.length must be \"m\"");
  if (r.string(units, "stamp_displacement", "manifest.units") != "m") r.fail("units.stamp_displacement must be \"m\"");
  metadata.scene = r.string(manifest, "scene", "manifest");
  metadata.description = r.string(manifest, "description", "manifest");
  const json& material = r.field(manifest, "material", "manifest");
  if (!material.is_object()) r.fail("field manifest.material is not an object");
  for (const auto& item : material.items()) metadata.material[item.key()] = r.number(material, item.key(), "manifest.material");
  // A manifest may carry no provenance.
  const auto provenance = manifest.find("provenance");
  if (provenance == manifest.end() || provenance->is_null()) return;
  Provenance p;
  try {
    p.scene = scene_file::parseSceneText(r.string(*provenance, "scene", "manifest.provenance"), "manifest.provenance.scene");
  } catch (const Error& e) {
    r.fail(e.what());
  }
  const json& hashes = r.field(*provenance, "file_hashes", "manifest.provenance");
  if (!hashes.is_object()) r.fail("field manifest.provenance.file_hashes is not an object");
  for (const auto& item : hashes.items()) p.fileHashes[item.key()] = r.string(hashes, item.key(), "manifest.provenance.file_hashes");
  if (provenance->contains("coarse_simulator")) p.coarseSimulator = r.string(*provenance, "coarse_simulator", "manifest.provenance");
  metadata.provenance = std::move(p);
}

// The blob's description in the manifest against the blob itself: size first, then checksum.
void checkBlob(const ManifestReader& r, const json& manifest, std::string_view blob, const std::string& blobPath) {
  const json& blobInfo = r.field(manifest, "stamp_blob", "manifest");
  if (r.string(blobInfo, "file", "manifest.stamp_blob") != kStampBlobFile) r.fail("stamp_blob.file must be " + std::string(kStampBlobFile));
  if (r.string(blobInfo, "dtype", "manifest.stamp_blob") != "float32_le") r.fail("stamp_blob.dtype must be float32_le");
  const json& sizeField = r.field(blobInfo, "size_bytes", "manifest.stamp_blob");
  if (!sizeField.is_number_unsigned()) r.fail("field manifest.stamp_blob.size_bytes is not a non-negative integer");
  const std::uint64_t declaredSize = sizeField.get<std::uint64_t>();
  const std::string declaredHash = r.string(blobInfo, "fnv1a64", "manifest.stamp_blob");
  if (blob.size() != declaredSize)
    throw IoError(blobPath + ": size " + std::to_string(blob.size()) + " bytes, manifest says " + std::to_string(declaredSize) +
                  " (truncated or extended)");
  const std::string actualHash = hex64(fnv1a64(blob.data(), blob.size()));
  if (actualHash != declaredHash)
    throw IoError(blobPath + ": checksum mismatch (fnv1a64 " + actualHash + ", manifest says " + declaredHash + ")");
}

// Example i of the manifest, its stamp taken from the blob at `offset` (advanced past it). `first` is
// example 0 (null while reading it): the set shares its descriptor layout and stamp grid.
Example readExample(const ManifestReader& r, const json& e, std::size_t i, const Example* first, std::string_view blob,
                    const std::string& blobPath, std::uint64_t& offset) {
  const std::string p = "manifest.examples[" + std::to_string(i) + "]";
  Example ex;
  const std::vector<double> c = r.numbers(r.field(e, "contact", p), p + ".contact", 3);
  ex.contact = Eigen::Vector3d(c[0], c[1], c[2]);
  const json& rows = r.field(e, "frame_rows", p);
  if (!rows.is_array() || rows.size() != 3) r.fail("field " + p + ".frame_rows is not 3 rows");
  for (int row = 0; row < 3; ++row) {
    const std::vector<double> v = r.numbers(rows[row], p + ".frame_rows[" + std::to_string(row) + "]", 3);
    for (int col = 0; col < 3; ++col) ex.frame(row, col) = v[col];
  }
  ex.rho = r.moments(e, "rho", p);
  ex.mu = r.moments(e, "mu", p);
  if (ex.rho.channels() != 1) r.fail("field " + p + ".rho must have 1 channel");
  if (ex.mu.channels() != 3) r.fail("field " + p + ".mu must have 3 channels");
  if (first && (!sameLayout(ex.rho, first->rho) || !sameLayout(ex.mu, first->mu)))
    r.fail("field " + p + " has descriptor orders that differ from example 0");
  ex.stampRadius = r.number(e, "stamp_radius", p);
  const int stampRows = r.integer(e, "stamp_rows", p);
  const int stampCols = r.integer(e, "stamp_cols", p);
  if (stampRows < 2 || stampCols < 2 || stampRows > 4096 || stampCols > 4096)
    r.fail("field " + p + " stamp size " + std::to_string(stampRows) + "x" + std::to_string(stampCols) + " outside [2, 4096]");
  // eq. (16) blends stamps node by node, so a set shares one grid: same size and radius.
  if (first && (stampRows != first->stamp.rows || stampCols != first->stamp.cols))
    r.fail("field " + p + " stamp size differs from example 0 (a set shares one stamp grid)");
  if (first && std::abs(ex.stampRadius - first->stampRadius) > 1e-9 * std::abs(first->stampRadius))
    r.fail("field " + p + ".stamp_radius differs from example 0 (a set shares one stamp grid)");
  // A manifest without stamp_layers holds surface stamps.
  if (e.is_object() && e.contains("stamp_layers")) ex.stampLayers = r.integer(e, "stamp_layers", p);
  if (ex.stampLayers < 1 || (ex.stampLayers > 1 && stampRows != ex.stampLayers * stampCols))
    r.fail("field " + p + ".stamp_layers " + std::to_string(ex.stampLayers) + " does not divide the stamp's " +
           std::to_string(stampRows) + " rows into square layers");
  if (first && ex.stampLayers != first->stampLayers) r.fail("field " + p + ".stamp_layers differs from example 0");
  const json& offsetField = r.field(e, "stamp_offset_bytes", p);
  if (!offsetField.is_number_unsigned() || offsetField.get<std::uint64_t>() != offset)
    r.fail("field " + p + ".stamp_offset_bytes is not " + std::to_string(offset) + " (stamps must be packed in order)");
  const std::uint64_t bytes = static_cast<std::uint64_t>(stampRows) * static_cast<std::uint64_t>(stampCols) * 3 * sizeof(float);
  if (offset + bytes > blob.size())
    throw IoError(blobPath + ": example " + std::to_string(i) + " stamp ends at byte " + std::to_string(offset + bytes) +
                  " past the blob's " + std::to_string(blob.size()));
  ex.stamp.create(stampRows, stampCols, CV_32FC3);
  std::memcpy(ex.stamp.ptr(), blob.data() + offset, bytes);
  offset += bytes;
  const json& pattern = r.field(e, "pattern", p);
  ex.pattern.indentDepth = r.number(pattern, "indent_depth", p + ".pattern");
  const std::vector<double> drag = r.numbers(r.field(pattern, "drag", p + ".pattern"), p + ".pattern.drag", 3);
  ex.pattern.drag = Eigen::Vector3d(drag[0], drag[1], drag[2]);
  ex.sceneId = r.string(e, "scene_id", p);
  // A manifest without plan lines leaves them unknown.
  if (e.is_object() && e.contains("plan_line")) {
    ex.planLine = r.integer(e, "plan_line", p);
    if (ex.planLine < -1) r.fail("field " + p + ".plan_line is below -1");
  }

  if (!cv::checkRange(ex.stamp, true)) throw IoError(blobPath + ": example " + std::to_string(i) + " stamp contains NaN or Inf");
  const std::string problem = exampleProblem(ex);
  if (!problem.empty()) r.fail("example " + std::to_string(i) + ": " + problem);
  return ex;
}

std::string readWholeFile(const std::string& path, const char* missing) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open (" + missing + "?)");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(path + ": read failed");
  return text.str();
}

}  // namespace

ExampleSet loadExampleSet(const std::string& directory) {
  const fs::path dir(directory);
  const std::string manifest = readWholeFile((dir / kManifestFile).string(), "missing manifest");
  const std::string blob = readWholeFile((dir / kStampBlobFile).string(), "missing stamp blob");
  return parseExampleSet(manifest, blob, directory);
}

ExampleSet parseExampleSet(std::string_view manifestText, std::string_view blob, const std::string& directory) {
  if (!hostIsLittleEndian()) throw IoError(directory + ": example sets are little-endian; big-endian hosts are not supported");
  const fs::path dir(directory);
  const ManifestReader r((dir / kManifestFile).string());
  const std::string blobPath = (dir / kStampBlobFile).string();
  json manifest;
  try {
    manifest = json::parse(manifestText.begin(), manifestText.end());
  } catch (const json::exception& e) {
    r.fail(std::string("not valid JSON: ") + e.what());
  }
  ExampleSet set;
  readHeader(r, manifest, set.metadata);
  checkBlob(r, manifest, blob, blobPath);
  const json& examples = r.field(manifest, "examples", "manifest");
  if (!examples.is_array() || examples.empty()) r.fail("field manifest.examples is not a non-empty array");
  std::uint64_t offset = 0;
  for (std::size_t i = 0; i < examples.size(); ++i)
    set.examples.push_back(readExample(r, examples[i], i, i > 0 ? &set.examples[0] : nullptr, blob, blobPath, offset));
  if (offset != blob.size())
    throw IoError(blobPath + ": " + std::to_string(blob.size() - offset) + " bytes not used by any example");
  return set;
}

}  // namespace deformation_enrichment::examples
