// libFuzzer target for editor session files (parse_session_text): freeform::Error is the only
// way out.
#include "editor/session.h"
#include "freeform/common/error.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)freeform::editor::parse_session_text(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
  } catch (const freeform::InternalError&) {
    throw;
  } catch (const freeform::Error&) {
  }
  return 0;
}
