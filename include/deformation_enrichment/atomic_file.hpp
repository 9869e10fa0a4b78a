#pragma once
// A file written whole or not at all: into PATH.tmp beside it, then renamed over PATH (a rename within one
// file system is atomic), so an error, a full disk or a crash leaves the previous file or none, never half.
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment {

/// Writes `contents` to `path`; throws IoError naming the path (the temporary file is removed then).
inline void writeFileAtomically(const std::filesystem::path& path, std::string_view contents) {
  const std::filesystem::path partial = path.string() + ".tmp";
  const auto fail = [&](const std::string& what) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw IoError(path.string() + ": " + what);
  };
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(path.string() + ": cannot open " + partial.string() + " for writing");
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) {
      out.close();
      fail("write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) fail("cannot rename the temporary file: " + ec.message());
}

}  // namespace deformation_enrichment
