// Shared helpers for the test executables: where data lives and scratch folders.
#pragma once

#include "build_paths.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace freeform::test {

// Committed small files (data/ in the repository).
inline std::filesystem::path data_dir() { return build_paths::data_dir(); }

// Unpacked libcgal-demo meshes (scripts/fetch-data.sh). Empty path if not present.
inline std::filesystem::path cgal_mesh_dir() {
  const char* env = std::getenv("FREEFORM_MESH_DIR");
  std::filesystem::path dir = env && *env ? env : build_paths::default_mesh_dir();
  return std::filesystem::is_directory(dir) ? dir : std::filesystem::path();
}

// True when tests must not skip for missing data (CI sets FREEFORM_REQUIRE_DATA=1).
inline bool data_required() {
  const char* env = std::getenv("FREEFORM_REQUIRE_DATA");
  return env && std::string(env) == "1";
}

// A fresh empty folder under the system temp dir, removed when the object dies.
class ScratchDir {
 public:
  ScratchDir() {
    auto base = std::filesystem::temp_directory_path();
    for (int i = 0;; ++i) {
      path_ = base / ("freeform-test-" + std::to_string(std::rand()) + "-" + std::to_string(i));
      if (std::filesystem::create_directory(path_)) break;
    }
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace freeform::test

// Skips (or fails, when data is required) if the libcgal-demo meshes are missing.
#define FREEFORM_REQUIRE_CGAL_MESHES()                                                         \
  do {                                                                                         \
    if (::freeform::test::cgal_mesh_dir().empty()) {                                           \
      if (::freeform::test::data_required()) FAIL() << "libcgal-demo meshes missing; run scripts/fetch-data.sh"; \
      GTEST_SKIP() << "libcgal-demo meshes missing; run scripts/fetch-data.sh";               \
    }                                                                                          \
  } while (0)
