// Settings validation and the continuous boundary-smoothness blend (docs/bcm.md).
#include "freeform/bcm/settings.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace freeform {

double smoothness_lambda(double c, int m) { return std::clamp(c - m + 1.0, 0.0, 1.0); }

namespace {

std::string num(double x) {
  if (std::isnan(x)) return "NaN";
  std::string s = std::to_string(x);
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

void check_c(double c, int k, const std::string& what, bool allow_default) {
  if (allow_default && c == Smoothness::kDefault) return;
  if (!std::isfinite(c))
    throw InvalidInput(what + " is " + num(c) + "; boundary smoothness must be a finite number in [0, " +
                       std::to_string(k - 1) + "]");
  if (c < 0.0 || c > k - 1.0)
    throw InvalidInput(what + " is " + num(c) + ", outside [0, " + std::to_string(k - 1) +
                       "] for order k = " + std::to_string(k) + " (0 = crease, k-1 = full C^(k-1))");
}

}  // namespace

void validate_settings(const BcmSettings& settings) {
  const int k = settings.order;
  if (k < 1 || k > 3)
    throw InvalidInput("order (stiffness) k = " + std::to_string(k) +
                       " is not supported; use 1 (membrane), 2 (thin plate) or 3 (minimal curvature variation)");
  check_c(settings.smoothness.outer, k, "outer boundary smoothness", true);
  check_c(settings.smoothness.inner, k, "inner boundary smoothness", true);
  const auto& segments = settings.smoothness.segments;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const std::string what = "boundary smoothness segment " + std::to_string(i);
    check_c(segments[i].value, k, what, false);
    for (Vertex v : segments[i].vertices)
      if (!v.is_valid()) throw InvalidInput(what + " names an invalid vertex");
  }
}

double resolved_outer(const BcmSettings& settings) {
  const double c = settings.smoothness.outer;
  return c == Smoothness::kDefault ? settings.order - 1.0 : c;
}

double resolved_inner(const BcmSettings& settings) {
  const double c = settings.smoothness.inner;
  return c == Smoothness::kDefault ? settings.order - 1.0 : c;
}

}  // namespace freeform
