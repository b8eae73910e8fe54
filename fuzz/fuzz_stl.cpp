// libFuzzer target for read_stl.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return freeform::fuzz::run(&freeform::read_stl, data, size);
}
