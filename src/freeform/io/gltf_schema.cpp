// The property types of the glTF 2.0 core schema, as a table: context (the kind of object),
// key, what its value must be. Extensions and extras are free-form except that `extensions`
// is an object of objects.
#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"
#include "freeform/io/gltf_util.h"

#include <fmt/format.h>

#include <string_view>

namespace freeform::gltf_detail {
namespace {

using json_messages::index_path;
using json_messages::key_path;
using json_messages::type_of;

enum class Kind {
  Object,    // an object of context `target`
  Objects,   // an array of objects of context `target`
  Ref,       // an index into the top-level array `target`
  Refs,      // an array of such indices
  AttrMap,   // an object whose values index accessors
  AttrMaps,  // an array of such objects (morph targets)
  Number,
  Numbers,  // an array of `size` numbers (0: any non-empty count)
  Integer,  // non-negative
  String,
  Strings,
  Bool,
};

struct Rule {
  std::string_view context;
  std::string_view key;
  Kind kind;
  std::string_view target = {};
  bool required = false;
  int size = 0;
};

constexpr bool kReq = true;

constexpr Rule kRules[] = {
    {"root", "asset", Kind::Object, "asset", kReq},
    {"root", "scene", Kind::Ref, "scenes"},
    {"root", "extensionsUsed", Kind::Strings},
    {"root", "extensionsRequired", Kind::Strings},
    {"root", "accessors", Kind::Objects, "accessor"},
    {"root", "animations", Kind::Objects, "animation"},
    {"root", "buffers", Kind::Objects, "buffer"},
    {"root", "bufferViews", Kind::Objects, "bufferView"},
    {"root", "cameras", Kind::Objects, "camera"},
    {"root", "images", Kind::Objects, "image"},
    {"root", "materials", Kind::Objects, "material"},
    {"root", "meshes", Kind::Objects, "mesh"},
    {"root", "nodes", Kind::Objects, "node"},
    {"root", "samplers", Kind::Objects, "sampler"},
    {"root", "scenes", Kind::Objects, "scene"},
    {"root", "skins", Kind::Objects, "skin"},
    {"root", "textures", Kind::Objects, "texture"},
    {"asset", "version", Kind::String, {}, kReq},
    {"asset", "minVersion", Kind::String},
    {"asset", "generator", Kind::String},
    {"asset", "copyright", Kind::String},
    {"accessor", "bufferView", Kind::Ref, "bufferViews"},
    {"accessor", "byteOffset", Kind::Integer},
    {"accessor", "componentType", Kind::Integer, {}, kReq},
    {"accessor", "normalized", Kind::Bool},
    {"accessor", "count", Kind::Integer, {}, kReq},
    {"accessor", "type", Kind::String, {}, kReq},
    {"accessor", "max", Kind::Numbers},
    {"accessor", "min", Kind::Numbers},
    {"accessor", "sparse", Kind::Object, "sparse"},
    {"sparse", "count", Kind::Integer, {}, kReq},
    {"sparse", "indices", Kind::Object, "sparseIndices", kReq},
    {"sparse", "values", Kind::Object, "sparseValues", kReq},
    {"sparseIndices", "bufferView", Kind::Ref, "bufferViews", kReq},
    {"sparseIndices", "byteOffset", Kind::Integer},
    {"sparseIndices", "componentType", Kind::Integer, {}, kReq},
    {"sparseValues", "bufferView", Kind::Ref, "bufferViews", kReq},
    {"sparseValues", "byteOffset", Kind::Integer},
    {"animation", "channels", Kind::Objects, "channel", kReq},
    {"animation", "samplers", Kind::Objects, "animationSampler", kReq},
    {"channel", "sampler", Kind::Integer, {}, kReq},
    {"channel", "target", Kind::Object, "channelTarget", kReq},
    {"channelTarget", "node", Kind::Ref, "nodes"},
    {"channelTarget", "path", Kind::String, {}, kReq},
    {"animationSampler", "input", Kind::Ref, "accessors", kReq},
    {"animationSampler", "interpolation", Kind::String},
    {"animationSampler", "output", Kind::Ref, "accessors", kReq},
    {"buffer", "uri", Kind::String},
    {"buffer", "byteLength", Kind::Integer, {}, kReq},
    {"bufferView", "buffer", Kind::Ref, "buffers", kReq},
    {"bufferView", "byteOffset", Kind::Integer},
    {"bufferView", "byteLength", Kind::Integer, {}, kReq},
    {"bufferView", "byteStride", Kind::Integer},
    {"bufferView", "target", Kind::Integer},
    {"camera", "orthographic", Kind::Object, "orthographic"},
    {"camera", "perspective", Kind::Object, "perspective"},
    {"camera", "type", Kind::String, {}, kReq},
    {"orthographic", "xmag", Kind::Number, {}, kReq},
    {"orthographic", "ymag", Kind::Number, {}, kReq},
    {"orthographic", "zfar", Kind::Number, {}, kReq},
    {"orthographic", "znear", Kind::Number, {}, kReq},
    {"perspective", "aspectRatio", Kind::Number},
    {"perspective", "yfov", Kind::Number, {}, kReq},
    {"perspective", "zfar", Kind::Number},
    {"perspective", "znear", Kind::Number, {}, kReq},
    {"image", "uri", Kind::String},
    {"image", "mimeType", Kind::String},
    {"image", "bufferView", Kind::Ref, "bufferViews"},
    {"material", "pbrMetallicRoughness", Kind::Object, "pbrMetallicRoughness"},
    {"material", "normalTexture", Kind::Object, "normalTextureInfo"},
    {"material", "occlusionTexture", Kind::Object, "occlusionTextureInfo"},
    {"material", "emissiveTexture", Kind::Object, "textureInfo"},
    {"material", "emissiveFactor", Kind::Numbers, {}, false, 3},
    {"material", "alphaMode", Kind::String},
    {"material", "alphaCutoff", Kind::Number},
    {"material", "doubleSided", Kind::Bool},
    {"pbrMetallicRoughness", "baseColorFactor", Kind::Numbers, {}, false, 4},
    {"pbrMetallicRoughness", "baseColorTexture", Kind::Object, "textureInfo"},
    {"pbrMetallicRoughness", "metallicFactor", Kind::Number},
    {"pbrMetallicRoughness", "roughnessFactor", Kind::Number},
    {"pbrMetallicRoughness", "metallicRoughnessTexture", Kind::Object, "textureInfo"},
    {"textureInfo", "index", Kind::Ref, "textures", kReq},
    {"textureInfo", "texCoord", Kind::Integer},
    {"normalTextureInfo", "index", Kind::Ref, "textures", kReq},
    {"normalTextureInfo", "texCoord", Kind::Integer},
    {"normalTextureInfo", "scale", Kind::Number},
    {"occlusionTextureInfo", "index", Kind::Ref, "textures", kReq},
    {"occlusionTextureInfo", "texCoord", Kind::Integer},
    {"occlusionTextureInfo", "strength", Kind::Number},
    {"mesh", "primitives", Kind::Objects, "primitive", kReq},
    {"mesh", "weights", Kind::Numbers},
    {"primitive", "attributes", Kind::AttrMap, {}, kReq},
    {"primitive", "indices", Kind::Ref, "accessors"},
    {"primitive", "material", Kind::Ref, "materials"},
    {"primitive", "mode", Kind::Integer},
    {"primitive", "targets", Kind::AttrMaps},
    {"node", "camera", Kind::Ref, "cameras"},
    {"node", "children", Kind::Refs, "nodes"},
    {"node", "skin", Kind::Ref, "skins"},
    {"node", "matrix", Kind::Numbers, {}, false, 16},
    {"node", "mesh", Kind::Ref, "meshes"},
    {"node", "rotation", Kind::Numbers, {}, false, 4},
    {"node", "scale", Kind::Numbers, {}, false, 3},
    {"node", "translation", Kind::Numbers, {}, false, 3},
    {"node", "weights", Kind::Numbers},
    {"sampler", "magFilter", Kind::Integer},
    {"sampler", "minFilter", Kind::Integer},
    {"sampler", "wrapS", Kind::Integer},
    {"sampler", "wrapT", Kind::Integer},
    {"scene", "nodes", Kind::Refs, "nodes"},
    {"skin", "inverseBindMatrices", Kind::Ref, "accessors"},
    {"skin", "skeleton", Kind::Ref, "nodes"},
    {"skin", "joints", Kind::Refs, "nodes", kReq},
    {"texture", "sampler", Kind::Ref, "samplers"},
    {"texture", "source", Kind::Ref, "images"},
};

class Checker {
 public:
  Checker(const Json& root, const std::string& path) : root_(root), path_(path) {}

  void object(const Json& j, std::string_view context, const std::string& where) const {
    expect(j.is_object(), where, "an object", j);
    for (const Rule& rule : kRules) {
      if (rule.context != context) continue;
      const auto it = j.find(rule.key);
      const std::string at = key_path(where, std::string(rule.key));
      if (it == j.end()) {
        if (rule.required) fail(fmt::format("{} is missing (required)", at));
        continue;
      }
      value(*it, rule, at);
    }
    if (const auto name = j.find("name"); name != j.end()) expect(name->is_string(), key_path(where, "name"), "a string", *name);
    if (const auto ext = j.find("extensions"); ext != j.end()) {
      expect(ext->is_object(), key_path(where, "extensions"), "an object", *ext);
      for (auto e = ext->begin(); e != ext->end(); ++e)
        expect(e->is_object(), key_path(key_path(where, "extensions"), e.key()), "an object", *e);
    }
  }

 private:
  void value(const Json& j, const Rule& rule, const std::string& at) const {
    switch (rule.kind) {
      case Kind::Object:
        return object(j, rule.target, at);
      case Kind::Objects:
        return each(j, at, [&](const Json& e, const std::string& a) { object(e, rule.target, a); });
      case Kind::Ref:
        return ref(j, rule.target, at);
      case Kind::Refs:
        return each(j, at, [&](const Json& e, const std::string& a) { ref(e, rule.target, a); });
      case Kind::AttrMap:
        return attributes(j, at);
      case Kind::AttrMaps:
        return each(j, at, [&](const Json& e, const std::string& a) { attributes(e, a); });
      case Kind::Number:
        return expect(j.is_number(), at, "a number", j);
      case Kind::Numbers:
        each(j, at, [&](const Json& e, const std::string& a) { expect(e.is_number(), a, "a number", e); });
        if (rule.size > 0 && j.size() != static_cast<std::size_t>(rule.size))
          fail(fmt::format("{} must hold {} numbers, got {}", at, rule.size, j.size()));
        return;
      case Kind::Integer:
        return integer(j, at);
      case Kind::String:
        return expect(j.is_string(), at, "a string", j);
      case Kind::Strings:
        return each(j, at, [&](const Json& e, const std::string& a) { expect(e.is_string(), a, "a string", e); });
      case Kind::Bool:
        return expect(j.is_boolean(), at, "true or false", j);
    }
  }

  template <class F>
  void each(const Json& j, const std::string& at, F&& f) const {
    expect(j.is_array(), at, "an array", j);
    for (std::size_t i = 0; i < j.size(); ++i) f(j[i], index_path(at, i));
  }

  void integer(const Json& j, const std::string& at) const {
    expect(j.is_number_integer(), at, "a non-negative integer", j);
    if (!j.is_number_unsigned() && j.get<std::int64_t>() < 0) expect(false, at, "a non-negative integer", j);
  }

  void ref(const Json& j, std::string_view target, const std::string& at) const {
    integer(j, at);
    const auto it = root_.find(target);
    const std::size_t size = it != root_.end() && it->is_array() ? it->size() : 0;
    const std::uint64_t i = j.get<std::uint64_t>();
    if (i >= size) fail(fmt::format("{} refers to {}[{}], which does not exist (the file has {})", at, target, i, size));
  }

  void attributes(const Json& j, const std::string& at) const {
    expect(j.is_object(), at, "an object", j);
    for (auto it = j.begin(); it != j.end(); ++it) ref(*it, "accessors", key_path(at, it.key()));
  }

  void expect(bool ok, const std::string& at, const char* what, const Json& j) const {
    if (!ok) fail(fmt::format("{} must be {}, got {}", at, what, type_of(j)));
  }
  [[noreturn]] void fail(const std::string& message) const { throw IoError(path_, 0, message); }

  const Json& root_;
  const std::string& path_;
};

}  // namespace

void check_schema(const Json& root, const std::string& path) {
  if (!root.is_object()) throw IoError(path, 0, "not a glTF file: the JSON text is not an object");
  Checker(root, path).object(root, "root", "");
}

}  // namespace freeform::gltf_detail
