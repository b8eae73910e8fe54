// Every libcgal-demo mesh in data/meshes/*.off either loads with the counts its header states
// or fails with an error that names the file. The header is parsed here independently of the
// library's OFF reader.
#include "freeform/common/error.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"
#include "test_support.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace freeform;

namespace {

struct OffHeader {
  long long vertices = -1, faces = -1;
};

// First three integers after the OFF keyword, skipping '#' comments.
OffHeader parse_header(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line, text;
  while (std::getline(in, line) && text.size() < 4096) {
    const auto hash = line.find('#');
    text += line.substr(0, hash) + "\n";
  }
  std::istringstream tokens(text);
  std::string keyword;
  tokens >> keyword;
  OffHeader h;
  if (keyword.find("OFF") == std::string::npos) return h;
  tokens >> h.vertices >> h.faces;
  return h;
}

}  // namespace

TEST(CgalDemoMeshes, EveryOffLoadsWithHeaderCountsOrFailsClearly) {
  FREEFORM_REQUIRE_CGAL_MESHES();
  int loaded = 0, refused = 0, manifold = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::cgal_mesh_dir())) {
    if (entry.path().extension() != ".off") continue;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    const OffHeader header = parse_header(entry.path());
    try {
      const ReadResult r = read_mesh(entry.path().string());
      ++loaded;
      EXPECT_EQ(static_cast<long long>(r.soup.positions.size()), header.vertices);
      const bool polygons = !r.warnings.empty();
      if (polygons)
        EXPECT_GT(static_cast<long long>(r.soup.faces.size()), header.faces);
      else
        EXPECT_EQ(static_cast<long long>(r.soup.faces.size()), header.faces);
      try {
        Mesh::from_soup(r.soup);
        ++manifold;
      } catch (const TopologyError& e) {
        EXPECT_THAT(e.what(), ::testing::HasSubstr("repair"));
        EXPECT_NO_THROW(Mesh::from_soup(r.soup, BuildOptions{.repair = true}));
      }
    } catch (const IoError& e) {
      ++refused;
      EXPECT_THAT(e.what(), ::testing::HasSubstr(name));
      std::cout << "refused " << e.what() << "\n";
    }
  }
  std::cout << loaded << " loaded (" << manifold << " manifold as is), " << refused << " refused\n";
  EXPECT_GT(loaded, 100);
}
