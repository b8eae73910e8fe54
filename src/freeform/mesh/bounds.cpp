#include "freeform/mesh/bounds.h"

#include <cmath>

namespace freeform {

double bounding_diagonal(const VertexData<Vec3>& positions) {
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = -lo;
  for (const Vec3& p : positions.raw())
    if (p.allFinite()) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  const double d = (hi - lo).norm();
  return d > 0.0 && std::isfinite(d) ? d : 1.0;
}

}  // namespace freeform
