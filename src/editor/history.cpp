#include "editor/history.h"

#include "freeform/common/error.h"

#include <algorithm>

namespace freeform::editor {
namespace {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

template <class T>
std::size_t heap(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

std::size_t delta_bytes(const Delta& d) {
  return std::visit(Overloaded{
                        [](const RegionDelta& r) { return heap(r.changes); },
                        [](const ApplyDelta& a) {
                          std::size_t n = heap(a.vertices) + heap(a.before) + heap(a.after) + heap(a.applied.support) +
                                          heap(a.applied.handles);
                          for (const EditHandle& h : a.applied.handles) n += heap(h.vertices);
                          return n;
                        },
                        [](const auto&) { return std::size_t{0}; },
                    },
                    d);
}

void shrink(Delta& d) {
  if (auto* r = std::get_if<RegionDelta>(&d)) r->changes.shrink_to_fit();
}

}  // namespace

void RegionRecorder::touch(Vertex v, const EditState& state) {
  if (index_.emplace(v.idx(), changes_.size()).second)
    changes_.push_back(VertexChange{v.idx(), state.handle_of(v), -1, state.support_flag(v), false});
}

RegionDelta RegionRecorder::finish(const EditState& state, std::vector<int>* touched_handles) const {
  RegionDelta r;
  for (VertexChange c : changes_) {
    c.new_support = state.support_flag(Vertex(c.vertex));
    c.new_handle = state.handle_of(Vertex(c.vertex));
    if (c.new_support == c.old_support && c.new_handle == c.old_handle) continue;
    if (touched_handles)
      for (int id : {c.old_handle, c.new_handle})
        if (id >= 0) touched_handles->push_back(id);
    r.changes.push_back(c);
  }
  if (touched_handles) {
    std::sort(touched_handles->begin(), touched_handles->end());
    touched_handles->erase(std::unique(touched_handles->begin(), touched_handles->end()), touched_handles->end());
  }
  return r;
}

bool Step::changes_solver() const {
  return std::any_of(deltas.begin(), deltas.end(), [](const Delta& d) { return !std::holds_alternative<TransformDelta>(d); });
}

bool Step::changes_regions() const {
  return std::any_of(deltas.begin(), deltas.end(), [](const Delta& d) {
    return std::holds_alternative<RegionDelta>(d) || std::holds_alternative<HandleAdded>(d) ||
           std::holds_alternative<HandleRemoved>(d) || std::holds_alternative<ParametersDelta>(d);
  });
}

std::size_t Step::memory_bytes() const {
  std::size_t n = sizeof(Step) + label.capacity() + heap(deltas);
  for (const Delta& d : deltas) n += delta_bytes(d);
  return n;
}

Step make_transition(const EditState& from, const EditState& to, std::string label) {
  if (from.n_vertices() != to.n_vertices())
    throw InvalidInput("cannot turn regions of " + std::to_string(from.n_vertices()) + " vertices into regions of " +
                       std::to_string(to.n_vertices()));
  std::vector<int> kept_from, kept_to;
  for (const HandleState& h : from.handles()) {
    const HandleState* t = to.find_handle(h.id);
    if (!t) continue;
    if (t->movable != h.movable) throw InvalidInput("handle " + std::to_string(h.id) + " changes between movable and immovable");
    kept_from.push_back(h.id);
  }
  bool added_seen = false;
  for (const HandleState& h : to.handles()) {
    const bool kept = from.find_handle(h.id) != nullptr;
    if (kept && added_seen) throw InvalidInput("new handles must come after the kept ones");
    if (kept) kept_to.push_back(h.id);
    added_seen = added_seen || !kept;
  }
  if (kept_from != kept_to) throw InvalidInput("kept handles must keep their order");

  Step s{std::move(label), {}};
  for (const HandleState& h : to.handles())
    if (!from.find_handle(h.id)) s.deltas.emplace_back(HandleAdded{h});
  RegionDelta r;
  for (int i = 0; i < from.n_vertices(); ++i) {
    const Vertex v(i);
    if (from.support_flag(v) == to.support_flag(v) && from.handle_of(v) == to.handle_of(v)) continue;
    r.changes.push_back({i, from.handle_of(v), to.handle_of(v), from.support_flag(v), to.support_flag(v)});
  }
  if (!r.changes.empty()) s.deltas.emplace_back(std::move(r));
  int removed = 0;
  for (std::size_t i = 0; i < from.handles().size(); ++i) {
    const HandleState& h = from.handles()[i];
    if (to.find_handle(h.id)) continue;
    s.deltas.emplace_back(HandleRemoved{static_cast<int>(i) - removed, h});
    ++removed;
  }
  for (const HandleState& h : from.handles()) {
    const HandleState* t = to.find_handle(h.id);
    if (t && !same_transform(h, *t))
      s.deltas.emplace_back(TransformDelta{h.id, h.manipulator, t->manipulator, h.matrix, t->matrix});
  }
  if (!(from.parameters() == to.parameters()))
    s.deltas.emplace_back(ParametersDelta{from.parameters(), to.parameters()});
  return s;
}

void play(const Delta& delta, EditState& state, bool forward) {
  std::visit(Overloaded{
                 [&](const RegionDelta& r) {
                   for (const VertexChange& c : r.changes)
                     state.set_vertex(Vertex(c.vertex), forward ? c.new_support : c.old_support,
                                      forward ? c.new_handle : c.old_handle);
                 },
                 [&](const HandleAdded& a) {
                   if (forward)
                     state.insert_handle(static_cast<int>(state.handles().size()), a.handle);
                   else
                     state.erase_handle(a.handle.id);
                 },
                 [&](const HandleRemoved& r) {
                   if (forward) {
                     FF_CHECK(state.handle_index(r.handle.id) == r.index, "handle removed from the wrong position");
                     state.erase_handle(r.handle.id);
                   } else {
                     state.insert_handle(r.index, r.handle);
                   }
                 },
                 [&](const ParametersDelta& p) { state.set_parameters(forward ? p.after : p.before); },
                 [&](const TransformDelta& t) {
                   state.set_transform(t.handle_id, forward ? t.after : t.before,
                                       forward ? t.matrix_after : t.matrix_before);
                 },
                 [](const ApplyDelta&) {},
             },
             delta);
}

void History::push(Step step) {
  if (step.empty()) return;
  for (const Step& s : redo_) bytes_ -= s.memory_bytes();
  redo_.clear();
  for (Delta& d : step.deltas) shrink(d);
  step.deltas.shrink_to_fit();
  bytes_ += step.memory_bytes();
  undo_.push_back(std::move(step));
  trim();
}

const Step& History::undo() {
  FF_CHECK(!undo_.empty(), "undo() without a step to undo");
  redo_.push_back(std::move(undo_.back()));
  undo_.pop_back();
  return redo_.back();
}

const Step& History::redo() {
  FF_CHECK(!redo_.empty(), "redo() without a step to redo");
  undo_.push_back(std::move(redo_.back()));
  redo_.pop_back();
  return undo_.back();
}

void History::clear() {
  undo_.clear();
  redo_.clear();
  bytes_ = 0;
}

void History::set_memory_limit(std::size_t bytes) {
  limit_ = bytes;
  trim();
}

void History::trim() {
  while (bytes_ > limit_ && undo_.size() > 1) {
    bytes_ -= undo_.front().memory_bytes();
    undo_.pop_front();
  }
}

}  // namespace freeform::editor
