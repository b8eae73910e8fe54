// --frame-log FILE: one JSON object per rendered frame (JSON Lines) with the frame's timings,
// collected in memory and written atomically when the editor exits, so a crash or kill leaves
// no half-written file. Fields (milliseconds unless noted):
//   frame (index), t_s (seconds since start), evaluate_ms, detail_ms (Document's frame
//   timings; 0 when no edit was evaluated this frame), normals_ms (vertex normals and bounds
//   of the displayed positions), upload_ms (Renderer::update_geometry plus glFinish), draw_ms
//   (mesh draw plus glFinish), ui_ms (ImGui build, overlays and render), frame_ms (whole loop
//   iteration up to the buffer swap), vertices, support (painted support vertices),
//   geometry (true if positions were uploaded this frame).
#pragma once

#include <string>
#include <vector>

namespace freeform::editor {

struct FrameRecord {
  long frame = 0;
  double t_s = 0;
  double evaluate_ms = 0, detail_ms = 0, normals_ms = 0, upload_ms = 0, draw_ms = 0, ui_ms = 0, frame_ms = 0;
  int vertices = 0, support = 0;
  bool geometry = false;
};

class FrameLog {
 public:
  FrameLog() = default;
  explicit FrameLog(std::string path) : path_(std::move(path)) {}
  bool enabled() const { return !path_.empty(); }
  void add(const FrameRecord& record);
  // Writes every record (atomic). Throws IoError.
  void write() const;
  std::size_t size() const { return lines_.size(); }

 private:
  std::string path_;
  std::vector<std::string> lines_;
};

}  // namespace freeform::editor
