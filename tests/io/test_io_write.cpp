// Writers (round trips for every format and encoding), dispatch by extension and atomic writes.
#include "io_test_util.h"

#include "freeform/io/file_util.h"

#include <algorithm>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <sys/stat.h>

namespace freeform::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// Coordinates that need all 17 significant digits, tiny and huge magnitudes, negative zero.
TriangleSoup awkward_soup() {
  TriangleSoup s;
  s.positions = {Vec3(0.1, 1.0 / 3.0, -2.0 / 7.0), Vec3(1e-300, 123456789.123456789, -0.0),
                 Vec3(std::nextafter(1.0, 2.0), 5e-324, 1e300), Vec3(-7.5, 0.2, 0.30000000000000004),
                 Vec3(3.14159265358979, 2.718281828459045, 1.4142135623730951)};
  s.faces = {Tri{0, 1, 2}, Tri{0, 2, 3}, Tri{3, 2, 1}, Tri{4, 0, 3}};
  return s;
}

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(WriteMesh, ExactRoundTripObjOffPly) {
  ScratchDir dir;
  const TriangleSoup soup = awkward_soup();
  struct Case {
    std::string file;
    bool binary;
  };
  for (const Case& c : {Case{"m.obj", true}, Case{"m.off", true}, Case{"m.ply", true}, Case{"m_ascii.ply", false}}) {
    SCOPED_TRACE(c.file);
    WriteOptions options;
    options.binary = c.binary;
    write_mesh((dir / c.file).string(), soup, options);
    const ReadResult r = read_mesh((dir / c.file).string());
    expect_same(r.soup, soup);
    EXPECT_TRUE(r.warnings.empty());
  }
  EXPECT_THAT(slurp(dir / "m.ply"), HasSubstr("format binary_little_endian 1.0"));
  EXPECT_THAT(slurp(dir / "m.ply"), HasSubstr("property double x"));
  EXPECT_THAT(slurp(dir / "m.ply"), HasSubstr("property list uchar int vertex_indices"));
  EXPECT_THAT(slurp(dir / "m_ascii.ply"), HasSubstr("format ascii 1.0"));
}

TEST(WriteMesh, StlRoundTripAsFloat) {
  ScratchDir dir;
  TriangleSoup soup = awkward_soup();
  soup.positions[2] = Vec3(2.5, -1e-3, 1e20);  // stays within float range
  soup.positions[1] = Vec3(1e-30, 123456789.123456789, -0.0);
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string path = (dir / (binary ? "b.stl" : "a.stl")).string();
    WriteOptions options;
    options.binary = binary;
    write_mesh(path, soup, options);
    EXPECT_EQ(slurp(path).rfind("solid", 0) == 0, !binary);
    const ReadResult r = read_mesh(path);
    ASSERT_EQ(r.soup.faces.size(), soup.faces.size());
    EXPECT_EQ(r.soup.positions.size(), soup.positions.size());
    for (std::size_t f = 0; f < soup.faces.size(); ++f) {
      for (int c = 0; c < 3; ++c) {
        const Vec3& expected = soup.positions[static_cast<std::size_t>(soup.faces[f][static_cast<std::size_t>(c)])];
        const Vec3& got = r.soup.positions[static_cast<std::size_t>(r.soup.faces[f][static_cast<std::size_t>(c)])];
        for (int k = 0; k < 3; ++k) EXPECT_EQ(got[k], static_cast<double>(static_cast<float>(expected[k])));
      }
    }
  }
}

// An OBJ's material libraries are named relative to its folder: written into another folder,
// the names lead from there to the same files (a material viewer finds them), the rest of the
// file byte for byte; in its own folder nothing changes.
TEST(WriteMesh, ObjInAnotherFolderStillFindsItsMaterialLibraries) {
  ScratchDir dir;
  fs::create_directories(dir / "in" / "lib");
  fs::create_directories(dir / "out");
  const std::string obj = "mtllib a.mtl lib/b.mtl /abs/c.mtl\r\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
  write_file_atomic((dir / "in" / "a.obj").string(), obj);
  write_file_atomic((dir / "in" / "a.mtl").string(), "newmtl red\n");
  write_file_atomic((dir / "in" / "lib" / "b.mtl").string(), "newmtl blue\n");
  const ReadResult r = read_mesh((dir / "in" / "a.obj").string());
  write_mesh((dir / "out" / "a.obj").string(), r, r.soup.positions);
  const std::string moved = read_file((dir / "out" / "a.obj").string());
  EXPECT_EQ(moved.substr(moved.find("\r\n")), obj.substr(obj.find("\r\n")));
  EXPECT_EQ(moved.substr(0, moved.find("\r\n")), "mtllib ../in/a.mtl ../in/lib/b.mtl /abs/c.mtl");
  EXPECT_EQ(read_file((dir / "out" / "../in/lib/b.mtl").string()), "newmtl blue\n");
  write_mesh((dir / "in" / "b.obj").string(), r, r.soup.positions);
  EXPECT_EQ(read_file((dir / "in" / "b.obj").string()), obj);
}

// The same for a PLY's texture as MeshLab names it in the header, in either encoding (a name
// may hold blanks: it is the rest of the comment line).
TEST(WriteMesh, PlyInAnotherFolderStillFindsItsTexture) {
  ScratchDir dir;
  fs::create_directories(dir / "in");
  fs::create_directories(dir / "out");
  const std::string head =
      "ply\nformat ascii 1.0\ncomment TextureFile tex dir/skin.png\r\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  write_file_atomic((dir / "in" / "a.ply").string(), head + body);
  const ReadResult r = read_mesh((dir / "in" / "a.ply").string());
  write_mesh((dir / "out" / "a.ply").string(), r, r.soup.positions);
  std::string expected = head;
  expected.replace(expected.find("tex dir"), 3, "../in/tex");
  EXPECT_EQ(read_file((dir / "out" / "a.ply").string()), expected + body);
  write_mesh((dir / "in" / "b.ply").string(), r, r.soup.positions);
  EXPECT_EQ(read_file((dir / "in" / "b.ply").string()), head + body);
  // Binary: the header grows, the body follows it unchanged.
  std::string binary = head;
  binary.replace(binary.find("ascii"), 5, "binary_little_endian");
  const std::string header_only = binary;
  for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f})
    binary.append(reinterpret_cast<const char*>(&v), 4);
  binary += '\x03';
  for (const int i : {0, 1, 2}) binary.append(reinterpret_cast<const char*>(&i), 4);
  write_file_atomic((dir / "in" / "c.ply").string(), binary);
  const ReadResult c = read_mesh((dir / "in" / "c.ply").string());
  write_mesh((dir / "out" / "c.ply").string(), c, c.soup.positions);
  const std::string out_bytes = read_file((dir / "out" / "c.ply").string());
  std::string expected_header = header_only;
  expected_header.replace(expected_header.find("tex dir"), 3, "../in/tex");
  EXPECT_EQ(out_bytes.substr(0, expected_header.size()), expected_header);
  EXPECT_EQ(out_bytes.substr(header_only.size() + 6), binary.substr(header_only.size()));
  EXPECT_EQ(read_mesh((dir / "out" / "c.ply").string()).soup.positions, r.soup.positions);
}

TEST(WriteMesh, FormatFromExtensionAndOverride) {
  ScratchDir dir;
  const TriangleSoup soup = tetra();
  write_mesh((dir / "UPPER.OBJ").string(), soup);
  EXPECT_EQ(slurp(dir / "UPPER.OBJ").substr(0, 1), "#");
  expect_same(read_mesh((dir / "UPPER.OBJ").string()).soup, soup);

  const std::string dat = (dir / "mesh.dat").string();
  EXPECT_THROW(write_mesh(dat, soup), IoError);
  WriteOptions wo;
  wo.format = MeshFormat::Off;
  write_mesh(dat, soup, wo);
  EXPECT_EQ(slurp(dat).substr(0, 4), "OFF\n");
  try {
    read_mesh(dat);
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mesh.dat"));
    EXPECT_THAT(e.what(), HasSubstr("extension"));
  }
  ReadOptions ro;
  ro.format = parse_mesh_format("OFF");
  expect_same(read_mesh(dat, ro).soup, soup);

  // An override beats the extension.
  const std::string fake = (dir / "fake.stl").string();
  wo.format = MeshFormat::Ply;
  wo.binary = false;
  write_mesh(fake, soup, wo);
  EXPECT_EQ(slurp(fake).substr(0, 4), "ply\n");
  ro.format = MeshFormat::Ply;
  expect_same(read_mesh(fake, ro).soup, soup);

  EXPECT_EQ(parse_mesh_format("Stl"), MeshFormat::Stl);
  EXPECT_THROW(parse_mesh_format("xyz"), InvalidInput);
  EXPECT_STREQ(format_name(MeshFormat::Ply), "ply");
  EXPECT_EQ(format_from_path("a/b.c/d.Off"), MeshFormat::Off);
}

TEST(WriteMesh, InvalidSoupThrowsAndLeavesTargetUntouched) {
  ScratchDir dir;
  const std::string path = (dir / "keep.obj").string();
  write_mesh(path, tetra());
  const std::string before = slurp(path);
  TriangleSoup bad = tetra();
  bad.faces.push_back(Tri{0, 1, 4});
  EXPECT_THROW(write_mesh(path, bad), InvalidInput);
  EXPECT_EQ(slurp(path), before);
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"keep.obj"});
}

TEST(WriteMesh, NeverWritesWhatTheReadersRefuse) {
  ScratchDir dir;
  for (const char* name : {"keep.off", "keep.obj", "keep.ply", "keep.stl"}) {
    const std::string path = (dir / name).string();
    write_mesh(path, tetra());
    const std::string before = slurp(path);
    TriangleSoup bad = tetra();
    bad.positions[2].y() = std::nan("");
    EXPECT_THAT([&] { write_mesh(path, bad); },
                ThrowsMessage<InvalidInput>(HasSubstr(std::string(name) + ": cannot write vertex 2: its coordinate nan is not finite")));
    EXPECT_EQ(slurp(path), before);
  }
  // 1e39 is a double but no float: STL (single precision) refuses it, the others keep it exactly.
  TriangleSoup big = tetra();
  big.positions[1].x() = 1e39;
  EXPECT_THAT([&] { write_mesh((dir / "big.stl").string(), big); },
              ThrowsMessage<InvalidInput>(HasSubstr("cannot write vertex 1: its coordinate 1e+39 is beyond the single precision of STL")));
  EXPECT_FALSE(std::filesystem::exists(dir / "big.stl"));
  write_mesh((dir / "big.off").string(), big);
  EXPECT_EQ(read_mesh((dir / "big.off").string()).soup.positions[1].x(), 1e39);
}

TEST(FileUtil, ReadFileErrorsNameTheFile) {
  ScratchDir dir;
  const std::string missing = (dir / "missing.obj").string();
  try {
    read_file(missing);
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.file(), missing);
    EXPECT_THAT(e.what(), HasSubstr(missing));
  }
  EXPECT_THROW(read_mesh(missing), IoError);
  try {
    read_file(dir.path().string());
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("directory"));
  }
  write_file_atomic((dir / "empty.obj").string(), "");
  EXPECT_EQ(read_file((dir / "empty.obj").string()), "");
  EXPECT_THAT(read_error(MeshFormat::Obj, read_file((dir / "empty.obj").string()), "empty.obj"),
              HasSubstr("empty file"));
}

TEST(FileUtil, AtomicWriteIntoMissingFolderThrowsAndCreatesNothing) {
  ScratchDir dir;
  const fs::path target = dir / "no" / "such" / "folder" / "m.obj";
  EXPECT_THROW(write_file_atomic(target.string(), "data"), IoError);
  EXPECT_THROW(write_mesh(target.string(), tetra()), IoError);
  EXPECT_FALSE(fs::exists(dir / "no"));
  EXPECT_TRUE(files_in(dir.path()).empty());
}

TEST(FileUtil, AtomicWriteReplacesAndLeavesNoTemporaries) {
  ScratchDir dir;
  const std::string path = (dir / "f.txt").string();
  write_file_atomic(path, "old");
  write_file_atomic(path, std::string("new\0data", 8));
  EXPECT_EQ(read_file(path), std::string("new\0data", 8));
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"f.txt"});
}

TEST(FileUtil, FailedRenameLeavesOldTargetIntact) {
  // The target is a non-empty folder: creating and writing the temporary works, the final
  // rename fails (even for root). The old target and its content must survive, the temporary
  // must be gone.
  ScratchDir dir;
  const fs::path target = dir / "mesh.obj";
  fs::create_directory(target);
  { std::ofstream(target / "inside.txt") << "precious"; }
  try {
    write_mesh(target.string(), tetra());
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mesh.obj"));
  }
  EXPECT_TRUE(fs::is_directory(target));
  EXPECT_EQ(slurp(target / "inside.txt"), "precious");
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"mesh.obj"});
}

TEST(FileUtil, SymlinkedTargetKeepsItsLinkAndTheTargetIsReplaced) {
  ScratchDir dir;
  fs::create_directory(dir / "real");
  const fs::path target = dir / "real" / "m.off", link = dir / "link.off";
  write_file_atomic(target.string(), "old");
  fs::create_symlink(target, link);
  write_file_atomic(link.string(), "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(read_file(target.string()), "new");
  EXPECT_EQ(files_in(dir.path()), (std::vector<std::string>{"link.off", "real"}));
  EXPECT_EQ(files_in(dir / "real"), std::vector<std::string>{"m.off"});
  // A dangling link: its target is created.
  const fs::path later = dir / "real" / "later.off", link2 = dir / "later-link.off";
  fs::create_symlink(later, link2);
  write_file_atomic(link2.string(), "created");
  EXPECT_EQ(read_file(later.string()), "created");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link2)));
}

TEST(FileUtil, SpecialFilesAreWrittenInPlace) {
  ASSERT_TRUE(is_special_file("/dev/null"));
  ASSERT_TRUE(is_special_file("-"));
  write_file_atomic("/dev/null", "discarded");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));  // not replaced by a regular file, even as root
  ScratchDir dir;
  const std::string fifo = (dir / "pipe").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_TRUE(is_special_file(fifo));
  EXPECT_FALSE(is_special_file((dir / "missing").string()));
}

TEST(FileUtil, UncommittedTemporariesAreRemovedOnTermination) {
  ScratchDir dir;
  const std::string path = (dir / "out.off").string();
  write_file_atomic(path, "before");
  for (int sig : {SIGTERM, SIGINT}) {
    EXPECT_EXIT(
        {
          std::signal(sig, SIG_DFL);  // as in a program that did not install its own handler
          PreparedFile f(path, "partial");
          std::raise(sig);  // killed between writing the temporary and renaming it
        },
        ::testing::KilledBySignal(sig), "");
    EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"out.off"}) << "signal " << sig;
    EXPECT_EQ(read_file(path), "before");
  }
  {
    PreparedFile f(path, "dropped");  // destroyed without commit
  }
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"out.off"});
  EXPECT_EQ(read_file(path), "before");
}

TEST(FileUtil, EndlessAndSparseInputsAreRefusedWithBoundedMemory) {
  try {
    read_file("/dev/zero");
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("not a regular file and did not end"));
  }
  ScratchDir dir;
  const std::string sparse = (dir / "sparse.off").string();
  { std::ofstream(sparse) << "OFF\n"; }
  fs::resize_file(sparse, std::uintmax_t{1} << 30);  // 1 GiB of holes
  try {
    read_file(sparse);
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("sparse file"));
  }
}

TEST(FileUtil, SameFileSeesLinksAndSpellings) {
  ScratchDir dir;
  const fs::path a = dir / "a.off";
  write_file_atomic(a.string(), "x");
  fs::create_symlink(a, dir / "s.off");
  fs::create_hard_link(a, dir / "h.off");
  EXPECT_TRUE(same_file(a.string(), (dir / "s.off").string()));
  EXPECT_TRUE(same_file(a.string(), (dir / "h.off").string()));
  EXPECT_TRUE(same_file(a.string(), (dir / "." / "a.off").string()));
  EXPECT_TRUE(same_file((dir / "new.off").string(), (dir / "." / "new.off").string()));  // neither exists
  EXPECT_FALSE(same_file(a.string(), (dir / "b.off").string()));
}

}  // namespace
}  // namespace freeform::test
