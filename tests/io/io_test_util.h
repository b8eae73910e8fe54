// Helpers for the I/O tests: in-memory readers, expected-error capture, binary builders.
#pragma once

#include "freeform/common/error.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "test_support.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace freeform::test {

inline std::string tiny(const std::string& file) { return (data_dir() / "tiny" / file).string(); }

// Reads in-memory data with the format's reader (everything it kept).
inline ReadResult read_file_mem(MeshFormat format, std::string_view data, const std::string& name) {
  ReadResult r;
  switch (format) {
    case MeshFormat::Obj:
      read_obj(data, name, r);
      break;
    case MeshFormat::Off:
      read_off(data, name, r);
      break;
    case MeshFormat::Ply:
      read_ply(data, name, r);
      break;
    case MeshFormat::Stl:
      read_stl(data, name, r);
      break;
    case MeshFormat::Gltf:
      read_gltf(data, name, r);
      break;
    case MeshFormat::Auto:
      ADD_FAILURE() << "no format";
      break;
  }
  return r;
}

inline TriangleSoup read_mem(MeshFormat format, std::string_view data, const std::string& name,
                             std::vector<std::string>* warnings = nullptr) {
  ReadResult r = read_file_mem(format, data, name);
  if (warnings) *warnings = r.warnings;
  return std::move(r.soup);
}

// The IoError message of reading `data` (empty, plus a test failure, when nothing is thrown).
inline std::string read_error(MeshFormat format, std::string_view data, const std::string& name) {
  try {
    read_mem(format, data, name);
  } catch (const IoError& e) {
    EXPECT_EQ(e.file(), name);
    return e.what();
  }
  ADD_FAILURE() << "expected an IoError for " << name;
  return {};
}

// Appends scalars in a chosen byte order (binary PLY / STL test files).
struct Bytes {
  bool big = false;
  std::string data;
  template <class T>
  Bytes& put(T value) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    const bool swap = big != (std::endian::native == std::endian::big);
    if (swap)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    data.append(reinterpret_cast<const char*>(b), sizeof(T));
    return *this;
  }
};

inline TriangleSoup tetra() {
  TriangleSoup s;
  s.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  s.faces = {Tri{0, 2, 1}, Tri{0, 1, 3}, Tri{0, 3, 2}, Tri{1, 2, 3}};
  return s;
}

inline void expect_same(const TriangleSoup& a, const TriangleSoup& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.positions[i][k], b.positions[i][k]) << "vertex " << i;
  }
  for (std::size_t i = 0; i < a.faces.size(); ++i) EXPECT_EQ(a.faces[i], b.faces[i]) << "face " << i;
}

}  // namespace freeform::test
