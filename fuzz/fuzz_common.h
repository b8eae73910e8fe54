// Shared body of the libFuzzer targets: run one reader on the input, accept freeform::Error,
// and check the invariants of every soup a reader returns. Anything else (another exception, an
// InternalError, a sanitizer report, a broken invariant) crashes and is reported by libFuzzer.
#pragma once

#include "freeform/common/error.h"
#include "freeform/io/mesh_io.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace freeform::fuzz {

using Reader = void (*)(std::string_view, const std::string&, ReadResult&);

inline int run(Reader reader, const std::uint8_t* data, std::size_t size) {
  ReadResult result;
  const TriangleSoup& soup = result.soup;
  try {
    reader(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz-input", result);
  } catch (const InternalError&) {
    throw;  // a bug: let it crash
  } catch (const Error&) {
    return 0;
  }
  if (soup.positions.empty() || soup.faces.empty()) std::abort();
  for (const Vec3& p : soup.positions)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) std::abort();
  const auto n = static_cast<long long>(soup.positions.size());
  for (const Tri& f : soup.faces)
    for (int v : f)
      if (v < 0 || v >= n) std::abort();
  // What a reader keeps besides the soup must index within itself.
  const MeshAttributes& a = result.attributes;
  for (const int v : a.polygons.corners)
    if (v < 0 || v >= n) std::abort();
  if (a.polygons.size() > 0 && a.triangle_polygon.size() != soup.faces.size()) std::abort();
  for (const CornerAttribute* c : {&a.uv, &a.normal})
    for (const int row : c->index)
      if (row < -1 || row >= c->rows() || c->index.size() != a.polygons.corners.size()) std::abort();
  for (const NamedAttribute& v : a.vertex)
    if (v.values.size() != soup.positions.size() * static_cast<std::size_t>(v.width)) std::abort();
  return 0;
}

}  // namespace freeform::fuzz
