#include "frame_log.h"

#include "freeform/io/file_util.h"

#include <nlohmann/json.hpp>

namespace freeform::editor {

void FrameLog::add(const FrameRecord& r) {
  if (!enabled()) return;
  nlohmann::ordered_json j;
  j["frame"] = r.frame;
  j["t_s"] = r.t_s;
  j["evaluate_ms"] = r.evaluate_ms;
  j["detail_ms"] = r.detail_ms;
  j["normals_ms"] = r.normals_ms;
  j["upload_ms"] = r.upload_ms;
  j["draw_ms"] = r.draw_ms;
  j["ui_ms"] = r.ui_ms;
  j["frame_ms"] = r.frame_ms;
  j["vertices"] = r.vertices;
  j["support"] = r.support;
  j["geometry"] = r.geometry;
  lines_.push_back(j.dump());
}

void FrameLog::write() const {
  if (!enabled()) return;
  std::string out;
  for (const auto& line : lines_) out += line + "\n";
  write_file_atomic(path_, out);
}

}  // namespace freeform::editor
