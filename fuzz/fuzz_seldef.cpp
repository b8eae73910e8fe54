// libFuzzer target for Botsch-Sorkine .sel and .def files: the first byte picks the reader,
// the rest is the file. freeform::Error is the only way out; labels must be 0, 1 or 2.
#include "freeform/common/error.h"
#include "freeform/regions/sel_file.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] & 1) {
      if (!freeform::parse_def(text, "fuzz.def").allFinite()) std::abort();
    } else {
      for (int label : freeform::parse_sel(text, "fuzz.sel", 121))
        if (label < 0 || label > 2) std::abort();
    }
  } catch (const freeform::InternalError&) {
    throw;
  } catch (const freeform::Error&) {
  }
  return 0;
}
