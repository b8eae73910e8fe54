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

using Reader = TriangleSoup (*)(std::string_view, const std::string&, std::vector<std::string>&);

inline int run(Reader reader, const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> warnings;
  TriangleSoup soup;
  try {
    soup = reader(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz-input", warnings);
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
  return 0;
}

}  // namespace freeform::fuzz
