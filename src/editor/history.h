// Undo/redo of the editor as compact deltas (issue 4): a step stores only what changed (the
// painted vertices, one handle, the parameters, one manipulator, the moved rest positions of
// an Apply), never a copy of the mesh or of the per-vertex arrays. The Document plays steps
// forward (do, redo) and backward (undo); doing an action is playing its step forward, so
// redo reproduces it exactly.
#pragma once

#include "editor/edit_state.h"
#include "freeform/edit/edit.h"

#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <variant>
#include <vector>

namespace freeform::editor {

struct VertexChange {
  int vertex = -1;
  int old_handle = -1, new_handle = -1;  // handle ids, -1 none
  bool old_support = false, new_support = false;
};

// Painted regions: one entry per vertex whose flag or handle changed.
struct RegionDelta {
  std::vector<VertexChange> changes;
};

// A handle appended at the end of the list (forward), removed again (backward). It has no
// vertices when added; a RegionDelta after it in the same step paints them.
struct HandleAdded {
  HandleState handle;
};

// A handle without vertices erased from position `index` (forward), re-inserted (backward).
struct HandleRemoved {
  int index = 0;
  HandleState handle;
};

struct ParametersDelta {
  EditParameters before, after;
};

// The manipulator and matrix of one handle.
struct TransformDelta {
  int handle_id = -1;
  Manipulator before, after;
  std::optional<Eigen::Affine3d> matrix_before, matrix_after;
};

// Apply: the rest positions that changed (bitwise) and the edit that was baked (the session's
// "applied" list). Manipulator resets are separate TransformDeltas in the same step.
struct ApplyDelta {
  std::vector<int> vertices;
  std::vector<Vec3> before, after;
  Edit applied;
};

using Delta = std::variant<RegionDelta, HandleAdded, HandleRemoved, ParametersDelta, TransformDelta, ApplyDelta>;

// Builds a RegionDelta while painting: remembers the old value of each vertex the first time
// it is touched; finish() reads the new values and drops vertices that ended unchanged.
class RegionRecorder {
 public:
  void touch(Vertex v, const EditState& state);  // call before changing v
  // The delta, and (if given) the sorted ids of the handles that gained or lost vertices.
  RegionDelta finish(const EditState& state, std::vector<int>* touched_handles = nullptr) const;

 private:
  std::vector<VertexChange> changes_;
  std::unordered_map<int, std::size_t> index_;
};

// One undo step: its deltas are played in order forward and in reverse order backward.
struct Step {
  std::string label;  // for menus: "paint support", "apply", ...
  std::vector<Delta> deltas;

  bool empty() const { return deltas.empty(); }
  // Whether playing it changes what the solver depends on (regions, handles, parameters, rest).
  bool changes_solver() const;
  bool changes_regions() const;  // the colours: painted regions, the handle list, smoothness
  std::size_t memory_bytes() const;
};

// The step that turns `from` into `to`: handles of `to` missing in `from` are added (appended,
// in `to` order), then the vertices that differ are repainted, then handles of `from` missing
// in `to` are removed, then changed transforms and parameters follow. Handles kept in both
// must keep their relative order and movable flag, and added ones must come after them in
// `to` (true for delete, clear and import); throws InvalidInput otherwise.
Step make_transition(const EditState& from, const EditState& to, std::string label);

// Plays the state part of a delta (everything but ApplyDelta, which is ignored here) forward
// or backward on `state`.
void play(const Delta& delta, EditState& state, bool forward);

class History {
 public:
  // Records a step that was just done; clears the redo stack. Empty steps are ignored. The
  // oldest steps are dropped while the total exceeds the memory limit (the newest is kept).
  void push(Step step);
  bool can_undo() const { return !undo_.empty(); }
  bool can_redo() const { return !redo_.empty(); }
  const Step* next_undo() const { return undo_.empty() ? nullptr : &undo_.back(); }
  const Step* next_redo() const { return redo_.empty() ? nullptr : &redo_.back(); }
  // Moves the newest step to the redo stack and returns it for the caller to play backward.
  // The reference is valid until the next call on this History. Precondition: can_undo().
  const Step& undo();
  // Moves the newest undone step back and returns it to be played forward. Precondition: can_redo().
  const Step& redo();
  void clear();

  std::size_t undo_size() const { return undo_.size(); }
  std::size_t redo_size() const { return redo_.size(); }
  // Heap and object bytes of every stored step (both stacks).
  std::size_t memory_bytes() const { return bytes_; }
  void set_memory_limit(std::size_t bytes);
  std::size_t memory_limit() const { return limit_; }

 private:
  std::deque<Step> undo_;
  std::vector<Step> redo_;
  std::size_t bytes_ = 0;
  std::size_t limit_ = std::size_t{512} << 20;

  void trim();
};

}  // namespace freeform::editor
