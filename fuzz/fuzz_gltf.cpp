// libFuzzer target for read_gltf (.gltf JSON and .glb containers), and the rewrite of what it
// reads into both containers. External buffers resolve beside "fuzz-input.gltf" (the working
// directory): a missing file is an IoError like any other malformed input.
#include "fuzz_common.h"

namespace {

void read_and_rewrite(std::string_view data, const std::string&, freeform::ReadResult& out) {
  freeform::read_gltf(data, "fuzz-input.gltf", out);
  std::vector<freeform::Vec3> moved = out.soup.positions;
  for (freeform::Vec3& p : moved) p = 0.5 * p + freeform::Vec3(0.25, 0, 0);
  std::vector<std::pair<std::string, std::string>> companions;
  for (const char* path : {"fuzz-output.gltf", "fuzz-output.glb"}) {
    companions.clear();
    const std::string bytes = out.source->rewrite(out, moved, companions, path);
    if (bytes.empty()) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return freeform::fuzz::run(&read_and_rewrite, data, size);
}
