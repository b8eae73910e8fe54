// libFuzzer target for read_obj.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return freeform::fuzz::run(&freeform::read_obj, data, size);
}
