// Internal: what the glTF reader keeps of a file to write it back (GltfSource), shared by
// gltf.cpp (reading) and gltf_rewrite.cpp. Not part of the public API.
#pragma once

#include "freeform/common/json_reader.h"
#include "freeform/io/mesh_attributes.h"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace freeform::gltf_detail {

// Where an accessor's elements lie in its buffer (bounds checked by the reader).
struct Layout {
  int accessor = -1;
  int buffer = -1;
  std::size_t start = 0;  // byte offset of element 0 in the buffer
  std::size_t stride = 0;
  int count = 0;
};

struct Buffer {
  enum class Origin { Glb, DataUri, File };
  Origin origin = Origin::File;
  bool loaded = false;
  std::string bytes;        // the whole GLB BIN chunk, decoded data URI or file
  std::string data_prefix;  // "data:application/octet-stream;base64," (DataUri)
  std::string file;         // the resolved path (File)
};

// A float VEC3 POSITION accessor: element i is soup vertex vertex[i], in a node whose world
// transform is x -> linear * x + translation.
struct PositionBlock {
  Layout layout;
  Eigen::Matrix3d linear;
  Eigen::Vector3d translation;
  std::vector<int> vertex;
};

// A float VEC3 NORMAL accessor: element i is row row_base + i of MeshAttributes::normal, in
// world space; to_local (the transpose of the node's linear part) takes it back.
struct NormalBlock {
  Layout layout;
  int row_base = 0;
  Eigen::Matrix3d to_local;
};

// A float VEC4 TANGENT accessor beside the NORMAL accessor `normal` (same element count).
struct TangentBlock {
  Layout layout;
  Layout normal;
  int row_base = 0;  // of the normals
};

struct GltfFile {
  Json json;
  std::string json_text;  // as read: its layout is kept (dump_like)
  bool glb = false;
  std::string glb_rest;  // chunks after BIN, verbatim
  std::string folder;    // of the file read
  std::vector<Buffer> buffers;
  std::vector<PositionBlock> positions;
  std::vector<NormalBlock> normals;
  std::vector<TangentBlock> tangents;
  std::string kept;  // FileSource::kept_only_by_rewrite
};

class GltfSource : public FileSource {
 public:
  explicit GltfSource(GltfFile file) : file_(std::move(file)) {}
  std::string rewrite(const ReadResult& file, std::span<const Vec3> positions,
                      std::vector<std::pair<std::string, std::string>>& companions,
                      const std::string& out_path) const override;
  bool binary() const override { return file_.glb; }
  std::string kept_only_by_rewrite() const override { return file_.kept; }

 private:
  GltfFile file_;
};

}  // namespace freeform::gltf_detail
