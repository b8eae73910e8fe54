#include "freeform/common/cpu_features.h"

namespace freeform {

bool cpu_has_avx2_fma() {
#if defined(__x86_64__) && defined(__GNUC__)
  // __builtin_cpu_init first: callers may run in static initializers, before libgcc's own.
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return has;
#else
  return false;
#endif
}

}  // namespace freeform
