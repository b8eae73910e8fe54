// The editor's model (issue 4), GL-free: the mesh, the edit being painted and manipulated, its
// undo history, the applied edits, the background precomputation and the displayed positions.
// The app calls update_display() once per frame and draws display_positions(); every
// mutation below is one undo step. Errors from the file and command methods are exceptions
// (InvalidInput / IoError / TopologyError with messages that say what to fix) thrown before
// anything changes; background failures are last_error(). The document never loses its mesh.
//
// Display: rest mesh deformed by the current manipulators with the newest finished solver.
// While a new one is computed the old one stays in use (with the manipulators of the handles
// it knows; the others stay put), so the old result stays on screen. After an Apply (or its
// undo) the rest mesh changed and, until the new solver is ready, the rest mesh is shown.
//
// Not thread-safe: use it from one thread (the UI thread); only the job runs elsewhere.
// Everything but open / open_mesh / load_session needs has_mesh() (commands throw
// InvalidInput "open a mesh first"; accessors such as rest_mesh() require it).
#pragma once

#include "editor/edit_state.h"
#include "editor/history.h"
#include "editor/precompute_job.h"
#include "freeform/edit/drag_session.h"
#include "freeform/io/mesh_io.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace freeform::editor {

// Support paints support flags; Handle paints into the active movable handle, Immovable into
// the active immovable handle (a new one is created if none of that kind is active). With
// `remove` Support clears flags and Handle/Immovable take vertices out of any handle of
// that kind. Handle vertices always count as support; a vertex painted into a handle leaves
// any other handle. Boundary paints the smoothness band (smoothness_band(): the fixed and
// handle vertices within k-1 rings of the free region; other vertices are skipped) into the
// active smoothness segment, a new one with c = 0 (a crease) if none is active; `remove`
// takes vertices out of the active segment, and a segment left empty is deleted.
enum class PaintMode { Support, Handle, Immovable, Boundary };

class Document {
 public:
  Document() = default;
  ~Document() = default;  // the job cancels and joins its worker
  Document(const Document&) = delete;
  Document& operator=(const Document&) = delete;

  // --- mesh ---
  // Reads a mesh (read_mesh + Mesh::from_soup, as `freeform deform` does) and starts a new,
  // clean document. Throws IoError / InvalidInput / TopologyError; the document is unchanged then.
  void open(const std::string& path);
  // Starts a document on an in-memory mesh (tests, generated meshes); `path` may be empty.
  void open_mesh(Mesh mesh, const std::string& path = {});
  bool has_mesh() const { return rest_ != nullptr; }
  const std::string& path() const { return path_; }  // the original mesh file
  const std::vector<std::string>& warnings() const { return warnings_; }  // reader warnings
  // The rest mesh of the current edit: the original with the applied edits baked in.
  const Mesh& rest_mesh() const { return *rest_; }
  const std::shared_ptr<const Mesh>& rest_mesh_ptr() const { return rest_; }
  const std::vector<Edit>& applied_edits() const { return applied_; }

  // --- state ---
  const EditState& state() const { return state_; }
  const EditParameters& parameters() const { return state_.parameters(); }
  // Empty if the regions can be precomputed, else what to paint ("paint a support region").
  // Updated after each change (at end_stroke for strokes).
  const std::string& regions_problem() const { return problem_; }
  int active_handle() const { return active_; }            // id or -1
  void set_active_handle(int id);                          // -1 or an existing id; not an undo step
  Vec3 handle_pivot(int id) const;                         // where a gizmo should sit (rest frame)

  // --- painting (one undo step per stroke) ---
  void begin_stroke(PaintMode mode, bool remove);  // ends a stroke still in progress
  // Paints immediately (region_version() changes, so colours update live). Throws
  // InvalidInput for a vertex outside the mesh or without begin_stroke (nothing painted then).
  void stroke(std::span<const Vertex> vertices);
  void end_stroke();  // records the step, re-centres pivots, requests a precompute
  bool stroking() const { return stroke_.has_value(); }
  // A whole selection (grow/shrink/flood/lasso results) as one step.
  void set_region(PaintMode mode, std::span<const Vertex> vertices, bool remove);

  // --- boundary smoothness segments (EditParameters::segments) ---
  // The vertices where boundary smoothness acts for the current regions and order (empty
  // while the regions have a problem); cached per region_version().
  const std::vector<Vertex>& smoothness_band();
  int active_segment() const { return active_segment_; }  // index or -1
  void set_active_segment(int index);                     // -1 or an existing index; not a step
  void set_segment_value(int index, double c);            // one step; c clamped to [0, k-1]
  void delete_segment(int index);                         // one step

  // --- handles, regions, parameters (one step each) ---
  int new_handle(bool movable);  // empty, becomes active; returns its id
  void delete_handle(int id);    // its vertices keep their own support flags
  void clear_regions();          // no support, no handles (parameters kept)
  void set_parameters(const EditParameters& p);  // normalized (order clamps smoothness)

  // --- manipulators ---
  // The drag path: live, no history, no precompute. An unset pivot keeps the handle's pivot.
  // Throws InvalidInput for an unknown or immovable handle or a non-finite/singular value.
  void preview_manipulator(int id, const Manipulator& m);
  // Ends a drag: sets `final` and records one step from `start` (the value when the drag
  // began). No step if they are identical. To cancel a drag, preview `start` again.
  void commit_manipulator(int id, const Manipulator& start, const Manipulator& final);

  // --- apply ---
  // Empty if apply() can run, else why not (regions problem, precompute running or failed).
  std::string apply_blocker() const;
  // Bakes the display positions into the rest mesh, resets the manipulators to the identity
  // (pivots re-centred), keeps the regions and records the applied edit. One undo step.
  // Throws InvalidInput with apply_blocker() if the current solver is not ready.
  void apply();

  // --- history ---
  bool can_undo() const { return history_.can_undo(); }
  bool can_redo() const { return history_.can_redo(); }
  void undo();  // ends a stroke in progress first; no-op without a step
  void redo();
  const History& history() const { return history_; }

  // --- display, once per frame ---
  // Adopts a finished solver and re-evaluates if anything changed. Never throws for a valid
  // document; `evaluated` is false when nothing had to be computed.
  // The nonlinear model iterates on a worker thread (DragSession): while it has not settled,
  // refining() is true and later updates show its newer iterates (call once per frame).
  FrameTimings update_display() { return update_display(false); }
  bool refining() const { return refining_; }
  // Blocks until the nonlinear model settled for the current transforms and shows its result
  // (tests, headless use; the linear model: update_display()).
  FrameTimings settle_display();
  const VertexData<Vec3>& display_positions() const { return display_; }
  const FrameTimings& last_timings() const { return timings_; }
  std::uint64_t display_version() const { return display_version_; }  // changes on re-evaluation
  // Changes when every display position may have changed (a new mesh or solver, an apply);
  // between two such changes only display_touched() move.
  std::uint64_t display_reset_version() const { return display_reset_version_; }
  // The vertices an evaluation writes (the solver's touched(); empty without a solver).
  std::span<const Vertex> display_touched() const;
  // Folded edges, flattened detail and flips of the display (EditSolver::problems, O(support)),
  // recomputed only when the display changed; nullopt while no solver evaluated it.
  std::optional<EditProblems> display_problems();
  std::uint64_t region_version() const { return region_version_; }    // changes with the colours

  // --- background precomputation ---
  bool precompute_running() const { return job_.running(); }
  JobStatus precompute_status() const { return job_.status(); }
  double precompute_fraction() const { return job_.status().fraction; }
  std::string precompute_stage() const { return job_.status().stage; }
  std::string last_error() const;  // the newest request's failure, empty if none
  void cancel_precompute() { job_.cancel(); }
  void recompute();                // requests the precompute again (after a cancel)
  // True if the solver in use was built for the current regions, parameters and rest mesh.
  bool solver_current() const;
  const std::shared_ptr<const PreparedSolver>& solver() const { return solver_; }
  // Blocks until the job is idle, then update_display() (tests, headless use).
  void wait_for_precompute();

  // --- files (atomic writes; IoError / InvalidInput) ---
  // Writes the display positions (write_mesh, format by extension) into the file as it was
  // read, so its polygons, texture coordinates, colours... are kept. Refuses the original
  // mesh file unless allow_overwrite_input. Clears dirty(). Returns what the target format
  // could not hold of the input (empty in the input's own format).
  std::vector<std::string> save_mesh(const std::string& path, bool allow_overwrite_input = false);
  // The current edit relative to rest_mesh() (vertex-index selectors, exact "matrix"
  // transforms): `freeform deform REST --edit FILE` reproduces the display bit for bit once
  // solver_current(). InvalidInput if the regions have a problem.
  void export_edit(const std::string& path) const;
  // Replaces the current edit by an edit file read against rest_mesh(); one undo step. The
  // file's handles get fresh ids; the first becomes active.
  void import_edit(const std::string& path);
  // Session files (session.h). Save needs a mesh opened from a file; clears dirty(). Load
  // reads the mesh, replays the applied edits with freeform::deform, restores the current
  // edit and starts its precompute; history is cleared. The document is unchanged on error.
  void save_session(const std::string& path);
  void load_session(const std::string& path);

  // Unsaved changes since open / save_mesh / save_session / load_session.
  bool dirty() const { return dirty_; }

 private:
  struct Stroke {
    PaintMode mode = PaintMode::Support;
    bool remove = false;
    RegionRecorder recorder;
    std::optional<HandleState> created;  // the handle this stroke made
    EditParameters parameters_before;    // Boundary strokes change the segments live
    std::vector<char> in_band;           // Boundary strokes: the band when the stroke began
  };

  std::shared_ptr<const Mesh> rest_;
  std::string path_;
  std::vector<std::string> warnings_;
  std::shared_ptr<const ReadResult> file_;  // the opened file; null for a mesh from memory
  EditState state_;
  History history_;
  std::vector<Edit> applied_;
  std::optional<Stroke> stroke_;
  int active_ = -1;
  int active_segment_ = -1;
  std::vector<Vertex> band_;
  std::uint64_t band_version_ = ~std::uint64_t{0};  // region_version_ of band_
  std::string problem_;
  bool dirty_ = false;
  bool input_overwritten_ = false;  // save_mesh replaced the original file

  std::shared_ptr<const PreparedSolver> solver_;
  std::uint64_t request_tag_ = 0;
  std::uint64_t adopted_generation_ = 0;
  VertexData<Vec3> display_;
  std::vector<Eigen::Affine3d> transforms_;
  bool base_valid_ = false;     // display_ holds the rest positions outside the solver's reach
  bool display_stale_ = true;   // re-evaluate on the next update_display
  std::unique_ptr<DragSession> drag_;  // over solver_'s EditSolver: destroyed before it
  bool refining_ = false;              // drag_ has not settled for transforms_
  FrameTimings timings_;
  std::uint64_t display_version_ = 0;
  std::uint64_t display_reset_version_ = 0;
  std::optional<EditProblems> problems_;
  std::uint64_t problems_version_ = 0;  // display_version_ the problems were computed for
  std::uint64_t region_version_ = 0;
  PrecomputeJob job_;  // last: destroyed (joined) first

  void require_mesh() const;
  FrameTimings update_display(bool settle);
  void reset(std::shared_ptr<const Mesh> rest, std::string path);
  void play_step(const Step& step, bool forward);
  void record(Step step);  // plays nothing: the step was just done
  void after_change(bool regions, bool solver);
  void request_precompute();
  int paint_target(PaintMode mode);
  void stroke_segment(std::span<const Vertex> vertices);
  TransformDelta recentre(int id) const;  // pivot -> rest centroid, map kept
};

}  // namespace freeform::editor
