#include "editor/document.h"

#include "editor/session.h"
#include "freeform/bcm/boundary_band.h"
#include "freeform/common/error.h"
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/repair.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <iterator>

namespace freeform::editor {
namespace {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal();
}

const char* paint_label(PaintMode mode, bool remove) {
  switch (mode) {
    case PaintMode::Support: return remove ? "erase support" : "paint support";
    case PaintMode::Handle: return remove ? "erase handle" : "paint handle";
    case PaintMode::Immovable: return remove ? "erase immovable handle" : "paint immovable handle";
    case PaintMode::Boundary: return remove ? "erase smoothness segment" : "paint smoothness segment";
  }
  return "paint";
}

}  // namespace

void Document::open(const std::string& path) {
  ReadResult read = read_mesh(path);
  Mesh mesh = manifold_mesh(read.soup, path);  // as `freeform deform`: no repair, vertex order kept
  reset(std::make_shared<const Mesh>(std::move(mesh)), path);
  warnings_ = read.warnings;
  file_ = std::make_shared<const ReadResult>(std::move(read));
}

void Document::open_mesh(Mesh mesh, const std::string& path) {
  reset(std::make_shared<const Mesh>(std::move(mesh)), path);
  warnings_.clear();
}

void Document::reset(std::shared_ptr<const Mesh> rest, std::string path) {
  job_.cancel();
  file_.reset();
  rest_ = std::move(rest);
  path_ = std::move(path);
  state_ = EditState(rest_->n_vertices());
  history_.clear();
  applied_.clear();
  stroke_.reset();
  active_ = -1;
  active_segment_ = -1;
  drag_.reset();
  solver_.reset();
  refining_ = false;
  ++request_tag_;
  display_ = rest_->positions();
  ++display_reset_version_;
  base_valid_ = true;
  display_stale_ = true;
  problem_ = state_.problem(*rest_);
  input_overwritten_ = false;
  dirty_ = false;
  ++region_version_;
}

void Document::require_mesh() const {
  if (!rest_) throw InvalidInput("open a mesh first");
}

void Document::set_active_handle(int id) {
  if (id != -1 && !state_.find_handle(id)) throw InvalidInput("there is no handle " + std::to_string(id));
  active_ = id;
}

Vec3 Document::handle_pivot(int id) const {
  const HandleState* h = state_.find_handle(id);
  if (!h) throw InvalidInput("there is no handle " + std::to_string(id));
  return h->manipulator.pivot ? *h->manipulator.pivot : centroid(*rest_, state_.handle_vertices(id));
}

void Document::play_step(const Step& step, bool forward) {
  const auto one = [&](const Delta& d) {
    if (const auto* a = std::get_if<ApplyDelta>(&d)) {
      auto mesh = std::make_shared<Mesh>(*rest_);
      const std::vector<Vec3>& values = forward ? a->after : a->before;
      for (std::size_t i = 0; i < a->vertices.size(); ++i) mesh->position(Vertex(a->vertices[i])) = values[i];
      rest_ = std::move(mesh);
      base_valid_ = false;
      if (forward) {
        applied_.push_back(a->applied);
      } else {
        FF_CHECK(!applied_.empty(), "undo of an apply without an applied edit");
        applied_.pop_back();
      }
    } else {
      play(d, state_, forward);
    }
  };
  if (forward)
    for (const Delta& d : step.deltas) one(d);
  else
    for (auto it = step.deltas.rbegin(); it != step.deltas.rend(); ++it) one(*it);
  after_change(step.changes_regions(), step.changes_solver());
}

void Document::after_change(bool regions, bool solver) {
  if (active_ != -1 && !state_.find_handle(active_)) active_ = -1;
  if (active_segment_ >= static_cast<int>(state_.parameters().settings.smoothness.segments.size())) active_segment_ = -1;
  if (regions) ++region_version_;
  display_stale_ = true;
  dirty_ = true;
  if (solver) request_precompute();
}

void Document::request_precompute() {
  ++request_tag_;
  problem_ = state_.problem(*rest_);
  if (!problem_.empty()) {
    job_.cancel();
    return;
  }
  PrecomputeRequest r;
  r.rest = rest_;
  r.edit = state_.to_edit(*rest_);
  for (const HandleState& h : state_.handles()) r.handle_ids.push_back(h.id);
  r.tag = request_tag_;
  job_.start(std::move(r));
}

void Document::recompute() {
  require_mesh();
  request_precompute();
}

TransformDelta Document::recentre(int id) const {
  const HandleState& h = *state_.find_handle(id);
  const Manipulator m = recentred(h.manipulator, centroid(*rest_, state_.handle_vertices(id)));
  return TransformDelta{id, h.manipulator, m, h.matrix, h.matrix};
}

void Document::begin_stroke(PaintMode mode, bool remove) {
  require_mesh();
  end_stroke();
  stroke_ = Stroke{mode, remove, {}, std::nullopt, state_.parameters(), {}};
  if (mode == PaintMode::Boundary) {
    stroke_->in_band.assign(static_cast<std::size_t>(state_.n_vertices()), 0);
    for (Vertex v : smoothness_band()) stroke_->in_band[static_cast<std::size_t>(v.idx())] = 1;
  }
}

const std::vector<Vertex>& Document::smoothness_band() {
  require_mesh();
  if (band_version_ != region_version_) {
    band_.clear();
    if (state_.problem(*rest_).empty())
      band_ = freeform::smoothness_band(*rest_, state_.regions(*rest_), state_.parameters().settings.order);
    band_version_ = region_version_;
  }
  return band_;
}

void Document::set_active_segment(int index) {
  if (index < -1 || index >= static_cast<int>(state_.parameters().settings.smoothness.segments.size()))
    throw InvalidInput("there is no smoothness segment " + std::to_string(index));
  active_segment_ = index;
}

void Document::set_segment_value(int index, double c) {
  require_mesh();
  EditParameters p = state_.parameters();
  if (index < 0 || index >= static_cast<int>(p.settings.smoothness.segments.size()))
    throw InvalidInput("there is no smoothness segment " + std::to_string(index));
  p.settings.smoothness.segments[static_cast<std::size_t>(index)].value = c;
  set_parameters(p);
}

void Document::delete_segment(int index) {
  require_mesh();
  EditParameters p = state_.parameters();
  if (index < 0 || index >= static_cast<int>(p.settings.smoothness.segments.size()))
    throw InvalidInput("there is no smoothness segment " + std::to_string(index));
  p.settings.smoothness.segments.erase(p.settings.smoothness.segments.begin() + index);
  set_parameters(p);
}

void Document::stroke_segment(std::span<const Vertex> vertices) {
  Stroke& s = *stroke_;
  EditParameters p = state_.parameters();
  if (active_segment_ < 0) {
    if (s.remove) return;
    p.settings.smoothness.segments.push_back(SmoothnessSegment{{}, 0.0});
    active_segment_ = static_cast<int>(p.settings.smoothness.segments.size()) - 1;
  }
  std::vector<Vertex>& seg = p.settings.smoothness.segments[static_cast<std::size_t>(active_segment_)].vertices;
  const std::size_t before = seg.size();
  std::vector<Vertex> painted;
  for (Vertex v : vertices)
    if (s.in_band[static_cast<std::size_t>(v.idx())]) painted.push_back(v);
  std::sort(painted.begin(), painted.end());
  if (s.remove) {
    std::vector<Vertex> kept;
    std::set_difference(seg.begin(), seg.end(), painted.begin(), painted.end(), std::back_inserter(kept));
    seg = std::move(kept);
  } else {
    std::vector<Vertex> merged;
    std::set_union(seg.begin(), seg.end(), painted.begin(), painted.end(), std::back_inserter(merged));
    seg = std::move(merged);
  }
  if (seg.size() == before && active_segment_ < static_cast<int>(state_.parameters().settings.smoothness.segments.size())) return;
  state_.set_parameters(p);
  ++region_version_;
}

int Document::paint_target(PaintMode mode) {
  const bool movable = mode == PaintMode::Handle;
  const HandleState* a = state_.find_handle(active_);
  if (a && a->movable == movable) return active_;
  HandleState h;
  h.id = state_.next_handle_id();
  h.movable = movable;
  state_.insert_handle(static_cast<int>(state_.handles().size()), h);
  stroke_->created = h;
  active_ = h.id;
  return h.id;
}

void Document::stroke(std::span<const Vertex> vertices) {
  if (!stroke_) throw InvalidInput("stroke() needs begin_stroke() first");
  for (Vertex v : vertices)
    if (v.idx() < 0 || v.idx() >= state_.n_vertices())
      throw InvalidInput("vertex " + std::to_string(v.idx()) + " is outside the mesh (" +
                         std::to_string(state_.n_vertices()) + " vertices)");
  if (vertices.empty()) return;
  if (stroke_->mode == PaintMode::Boundary) return stroke_segment(vertices);
  Stroke& s = *stroke_;
  const bool handle_mode = s.mode != PaintMode::Support;
  const int target = handle_mode && !s.remove ? paint_target(s.mode) : -1;
  for (Vertex v : vertices) {
    const bool sup = state_.support_flag(v);
    const int h = state_.handle_of(v);
    bool new_sup = sup;
    int new_h = h;
    if (!handle_mode)
      new_sup = !s.remove;
    else if (!s.remove)
      new_h = target;
    else if (h >= 0 && state_.find_handle(h)->movable == (s.mode == PaintMode::Handle))
      new_h = -1;
    if (new_sup == sup && new_h == h) continue;
    s.recorder.touch(v, state_);
    state_.set_vertex(v, new_sup, new_h);
  }
  ++region_version_;
}

void Document::end_stroke() {
  if (!stroke_) return;
  Stroke s = std::move(*stroke_);
  stroke_.reset();
  Step step{paint_label(s.mode, s.remove), {}};
  if (s.mode == PaintMode::Boundary) {
    EditParameters p = state_.parameters();
    const auto active = static_cast<std::size_t>(active_segment_);
    if (active_segment_ >= 0 && active < p.settings.smoothness.segments.size() && p.settings.smoothness.segments[active].vertices.empty()) {
      p.settings.smoothness.segments.erase(p.settings.smoothness.segments.begin() + active_segment_);
      active_segment_ = -1;
    }
    state_.set_parameters(p);
    ++region_version_;
    if (p == s.parameters_before) return;  // nothing painted: no step
    step.deltas.emplace_back(ParametersDelta{s.parameters_before, p});
  }
  if (s.created) step.deltas.emplace_back(HandleAdded{*s.created});
  std::vector<int> touched;
  RegionDelta r = s.recorder.finish(state_, &touched);
  if (!r.changes.empty()) step.deltas.emplace_back(std::move(r));
  for (int id : touched) {  // pivots follow the handle's vertices (the map is kept)
    if (!state_.find_handle(id) || state_.handle_size(id) == 0) continue;
    TransformDelta d = recentre(id);
    HandleState before{id, true, d.before, d.matrix_before}, after{id, true, d.after, d.matrix_after};
    if (same_transform(before, after)) continue;
    play(d, state_, true);
    step.deltas.emplace_back(std::move(d));
  }
  if (step.empty()) return;
  const bool regions = step.changes_regions();
  history_.push(std::move(step));
  after_change(regions, true);
}

void Document::set_region(PaintMode mode, std::span<const Vertex> vertices, bool remove) {
  begin_stroke(mode, remove);
  try {
    stroke(vertices);
  } catch (...) {
    stroke_.reset();  // the range check threw before anything was painted
    throw;
  }
  end_stroke();
}

int Document::new_handle(bool movable) {
  require_mesh();
  end_stroke();
  HandleState h;
  h.id = state_.next_handle_id();
  h.movable = movable;
  Step step{movable ? "new handle" : "new immovable handle", {HandleAdded{h}}};
  play_step(step, true);
  history_.push(std::move(step));
  active_ = h.id;
  return h.id;
}

void Document::delete_handle(int id) {
  require_mesh();
  end_stroke();
  if (!state_.find_handle(id)) throw InvalidInput("there is no handle " + std::to_string(id));
  EditState to = state_;
  for (Vertex v : to.handle_vertices(id)) to.set_vertex(v, to.support_flag(v), -1);
  to.erase_handle(id);
  Step step = make_transition(state_, to, "delete handle");
  play_step(step, true);
  history_.push(std::move(step));
}

void Document::clear_regions() {
  require_mesh();
  end_stroke();
  EditState to(state_.n_vertices());
  to.set_parameters(state_.parameters());
  Step step = make_transition(state_, to, "clear regions");
  if (step.empty()) return;
  play_step(step, true);
  history_.push(std::move(step));
}

void Document::set_parameters(const EditParameters& p) {
  require_mesh();
  end_stroke();
  const EditParameters next = normalized(p);
  if (next == state_.parameters()) return;
  Step step{"parameters", {ParametersDelta{state_.parameters(), next}}};
  play_step(step, true);
  history_.push(std::move(step));
}

void Document::preview_manipulator(int id, const Manipulator& m) {
  const HandleState* h = state_.find_handle(id);
  if (!h) throw InvalidInput("there is no handle " + std::to_string(id));
  if (!h->movable) throw InvalidInput("handle " + std::to_string(id) + " is immovable; it cannot be moved");
  Manipulator next = m;
  if (!next.pivot) next.pivot = h->manipulator.pivot;
  const std::optional<Eigen::Affine3d> matrix = h->matrix;
  state_.set_transform(id, next, matrix);
  display_stale_ = true;
}

void Document::commit_manipulator(int id, const Manipulator& start, const Manipulator& final) {
  const HandleState* h = state_.find_handle(id);
  if (!h) throw InvalidInput("there is no handle " + std::to_string(id));
  if (!h->movable) throw InvalidInput("handle " + std::to_string(id) + " is immovable; it cannot be moved");
  TransformDelta d{id, start, final, h->matrix, h->matrix};
  if (!d.before.pivot) d.before.pivot = h->manipulator.pivot;
  if (!d.after.pivot) d.after.pivot = h->manipulator.pivot;
  (void)HandleState{id, true, d.before, d.matrix_before}.transform();  // undo must not throw later
  state_.set_transform(id, d.after, d.matrix_after);
  display_stale_ = true;
  if (same_transform(HandleState{id, true, d.before, d.matrix_before}, HandleState{id, true, d.after, d.matrix_after})) return;
  history_.push(Step{"move handle", {std::move(d)}});
  dirty_ = true;
}

std::string Document::apply_blocker() const {
  if (!rest_) return "open a mesh first";
  if (stroke_) return "finish the stroke first";
  if (!problem_.empty()) return problem_;
  if (solver_current()) return {};
  const std::shared_ptr<const PreparedSolver> s = job_.solver();  // finished, not adopted yet
  if (s && s->tag() == request_tag_ && s->rest() == rest_) return {};
  if (job_.running()) return "the precomputation is still running: apply when it has finished";
  const std::string error = last_error();
  if (!error.empty()) return "the precomputation failed: " + error;
  return "the precomputation was cancelled: recompute first";
}

void Document::apply() {
  end_stroke();
  if (const std::string why = apply_blocker(); !why.empty()) throw InvalidInput("cannot apply: " + why);
  settle_display();  // bake the nonlinear model's result, not an iterate on its way
  FF_CHECK(solver_current(), "apply without a current solver");
  ApplyDelta a;
  a.applied = state_.to_edit(*rest_);
  for (int i = 0; i < rest_->n_vertices(); ++i) {
    const Vec3& before = rest_->position(Vertex(i));
    const Vec3& after = display_[Vertex(i)];
    if (std::memcmp(before.data(), after.data(), sizeof(double) * 3) == 0) continue;
    a.vertices.push_back(i);
    a.before.push_back(before);
    a.after.push_back(after);
  }
  Step step{"apply", {}};
  step.deltas.emplace_back(std::move(a));
  play_step(step, true);  // bakes; the manipulator resets below need the new rest centroids
  for (const HandleState& h : state_.handles()) {
    if (!h.movable) continue;
    Manipulator identity;
    identity.pivot = centroid(*rest_, state_.handle_vertices(h.id));
    TransformDelta d{h.id, h.manipulator, identity, h.matrix, std::nullopt};
    step.deltas.emplace_back(std::move(d));
  }
  for (std::size_t i = 1; i < step.deltas.size(); ++i) play(step.deltas[i], state_, true);
  history_.push(std::move(step));
}

void Document::undo() {
  end_stroke();
  if (!history_.can_undo()) return;
  play_step(history_.undo(), false);
}

void Document::redo() {
  end_stroke();
  if (!history_.can_redo()) return;
  play_step(history_.redo(), true);
}

FrameTimings Document::update_display(bool settle) {
  FrameTimings t;
  if (!rest_) return t;
  if (const std::uint64_t g = job_.generation(); g != adopted_generation_) {
    adopted_generation_ = g;
    std::shared_ptr<const PreparedSolver> s = job_.solver();
    if (s && s != solver_ && s->rest() == rest_) {  // a solver of an older rest mesh is useless
      drag_.reset();
      solver_ = std::move(s);
      base_valid_ = false;
      display_stale_ = true;
    }
  }
  if (!display_stale_ && base_valid_ && !(settle && refining_)) return t;
  const auto start = std::chrono::steady_clock::now();
  const bool reset = !base_valid_;
  if (!base_valid_) {
    display_ = rest_->positions();
    ++display_reset_version_;
    base_valid_ = true;
  }
  if (solver_ && solver_->rest() == rest_) {
    const std::vector<int>& ids = solver_->movable_ids();
    transforms_.resize(ids.size());
    for (std::size_t m = 0; m < ids.size(); ++m) {
      const HandleState* h = state_.find_handle(ids[m]);
      transforms_[m] = h && h->movable ? state_.transform(ids[m], *rest_) : Eigen::Affine3d::Identity();
    }
    // A reset display needs every touched vertex written, so a fresh session (a new solver
    // or mesh: its first frame starts the model from these transforms).
    if (reset) drag_.reset();  // its worker must stop before a new one drives the same model
    if (!drag_) drag_ = std::make_unique<DragSession>(solver_->solver());
    const DragFrame f = settle ? drag_->finish(transforms_, display_) : drag_->frame(transforms_, display_);
    refining_ = !f.settled;
    display_stale_ = refining_;
    if (!f.written) return t;
    t = {f.evaluate_ms, f.reconstruction_ms, 0.0, true, f.state.iterations, f.state.step, f.settled && f.state.converged,
         f.predicted};
  } else {
    refining_ = false;
    display_stale_ = false;
  }
  t.evaluated = true;
  t.total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  timings_ = t;
  ++display_version_;
  return t;
}

FrameTimings Document::settle_display() { return update_display(true); }

std::span<const Vertex> Document::display_touched() const {
  if (solver_ && solver_->rest() == rest_) return solver_->touched();
  return {};
}

std::optional<EditProblems> Document::display_problems() {
  if (!solver_ || solver_->rest() != rest_ || !base_valid_) return std::nullopt;
  if (!problems_ || problems_version_ != display_version_) {
    problems_ = solver_->solver().problems(display_);
    problems_version_ = display_version_;
  }
  return problems_;
}

std::string Document::last_error() const {
  const JobStatus s = job_.status();
  return s.state == JobState::Failed && s.tag == request_tag_ ? s.error : std::string();
}

bool Document::solver_current() const {
  return solver_ && rest_ && solver_->tag() == request_tag_ && solver_->rest() == rest_;
}

void Document::wait_for_precompute() {
  job_.wait();
  update_display();
}

std::vector<std::string> Document::save_mesh(const std::string& path, bool allow_overwrite_input) {
  require_mesh();
  const bool input = !path_.empty() && same_file(path, path_);
  if (input && !allow_overwrite_input)
    throw InvalidInput("\"" + path + "\" is the input mesh: save under another name or allow overwriting the input");
  settle_display();
  // The file as it was read, with the display positions: its polygons, UVs, colours... kept.
  ReadResult generated;
  if (!file_) generated.soup = rest_->to_soup();
  std::vector<std::string> dropped = write_mesh(path, file_ ? *file_ : generated, display_.raw(), {});
  input_overwritten_ = input_overwritten_ || input;
  dirty_ = false;
  return dropped;
}

void Document::export_edit(const std::string& path) const {
  require_mesh();
  if (const std::string why = state_.problem(*rest_); !why.empty()) throw InvalidInput("cannot export the edit: " + why);
  write_edit_file(path, state_.to_edit(*rest_));
}

void Document::import_edit(const std::string& path) {
  require_mesh();
  end_stroke();
  const Edit edit = read_edit_file(path, *rest_);
  const EditState to = EditState::from_edit(edit, *rest_, state_.next_handle_id());
  Step step = make_transition(state_, to, "import edit");
  play_step(step, true);
  history_.push(std::move(step));
  active_ = to.handles().empty() ? -1 : to.handles().front().id;
}

void Document::save_session(const std::string& path) {
  require_mesh();
  if (path_.empty()) throw InvalidInput("the mesh has no file: save it first, a session refers to the mesh file");
  if (input_overwritten_)
    throw InvalidInput("the original mesh file " + path_ + " was overwritten: a session needs the original mesh");
  end_stroke();
  Session s;
  const fs::path mesh = fs::absolute(path_).lexically_normal();
  s.mesh_path = mesh.string();
  s.mesh_relative = mesh.lexically_relative(fs::absolute(path).parent_path()).string();
  s.n_vertices = rest_->n_vertices();
  for (const Edit& e : applied_) s.applied.push_back(edit_to_json(e));
  s.current = state_;
  s.active_handle = active_;
  write_session_file(path, s);
  dirty_ = false;
}

void Document::load_session(const std::string& path) {
  LoadedSession loaded = load_session_file(path);  // throws before anything changes
  reset(std::make_shared<const Mesh>(std::move(loaded.rest)), loaded.mesh_file);
  warnings_ = std::move(loaded.warnings);
  file_ = std::move(loaded.file);
  applied_ = std::move(loaded.applied);
  state_ = std::move(loaded.current);
  active_ = loaded.active_handle;
  after_change(true, true);
  dirty_ = false;
}

}  // namespace freeform::editor
