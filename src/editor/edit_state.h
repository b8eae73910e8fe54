// The editor's current edit as plain data (issue 4): painted regions (a support flag and a
// handle id per vertex), the handles with their manipulators, and the BCM parameters.
// No history here: the Document changes it through the primitives below and records deltas
// (history.h). to_edit() turns it into the Edit the CLI replays (docs/edit-format.md).
#pragma once

#include "freeform/edit/edit.h"
#include "freeform/edit/manipulator.h"
#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"


#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace freeform::editor {

// The edit's settings in the library's one form (edit.h: order, smoothness and its segments,
// anisotropic, multiresolution, the model and its options, allow_unanchored), so whatever an
// edit file or session holds survives the editor; with the editor's defaults (order 3, the
// smoothness written out for the sliders). The editor keeps a segment's painted vertices;
// to_edit() drops those outside the current smoothness band.
struct EditParameters : EditSettings {
  EditParameters();
  bool operator==(const EditParameters&) const = default;
};

// Throws InvalidInput for an order outside {1, 2, 3} or a non-finite smoothness; clamps
// outer/inner and segment values into [0, order-1] (so lowering the order clamps them).
EditParameters normalized(EditParameters p);

struct HandleState {
  int id = -1;                            // stable, never reused within a document
  bool movable = true;                    // false: immovable (held like fixed surface)
  Manipulator manipulator;                // pivot set explicitly (the centroid, see recentred)
  std::optional<Eigen::Affine3d> matrix;  // an imported general affine map, applied first

  // The map the editor evaluates: manipulator.to_affine(pivot) * matrix, exactly (the matrix
  // alone while the manipulator is the identity). `default_pivot` is used if pivot is unset.
  // Throws InvalidInput for a non-finite or singular manipulator.
  Eigen::Affine3d transform(const Vec3& default_pivot = Vec3::Zero()) const;
};

// Bitwise equality of the manipulators and matrices (the undo tests compare exactly).
bool same_transform(const HandleState& a, const HandleState& b);
bool operator==(const HandleState& a, const HandleState& b);

// `m` with its pivot moved to `pivot` and the translation adjusted so the affine map stays the
// same (to rounding; exactly for a pure translation): a handle grown while moved keeps moving.
Manipulator recentred(const Manipulator& m, const Vec3& pivot);

// Mean of the rest positions of `vertices` (summed in the given order, as BcmSolver does for
// its default pivot). Zero for an empty list.
Vec3 centroid(const Mesh& rest, const std::vector<Vertex>& vertices);

class EditState {
 public:
  EditState() = default;
  explicit EditState(int n_vertices);

  int n_vertices() const { return static_cast<int>(handle_.size()); }

  // --- per vertex ---
  bool support_flag(Vertex v) const { return support_[static_cast<std::size_t>(v.idx())] != 0; }
  int handle_of(Vertex v) const { return handle_[static_cast<std::size_t>(v.idx())]; }  // id or -1
  // Handle vertices count as support whatever their own flag says.
  bool in_support(Vertex v) const { return support_flag(v) || handle_of(v) >= 0; }
  const std::vector<std::uint8_t>& support_flags() const { return support_; }  // #V, for colouring
  const std::vector<int>& handle_ids() const { return handle_; }               // #V, -1 none

  // --- handles, in region order (the order of to_edit and the solver) ---
  const std::vector<HandleState>& handles() const { return handles_; }
  const HandleState* find_handle(int id) const;  // nullptr if there is none
  int handle_index(int id) const;                // -1 if there is none
  int next_handle_id() const { return next_id_; }
  std::vector<Vertex> handle_vertices(int id) const;  // sorted; O(#V)

  // --- counts (maintained incrementally, O(1)) ---
  int n_support() const { return n_support_; }  // including handle vertices
  int n_handle_vertices() const { return n_handle_vertices_; }  // in any handle
  int n_free() const { return n_support_ - n_handle_vertices(); }
  int handle_size(int id) const;                // 0 for an unknown id

  const EditParameters& parameters() const { return params_; }

  // --- primitives (no history; the Document records a delta for each) ---
  // Sets one vertex; handle_id must be -1 or an existing handle (InvalidInput otherwise).
  void set_vertex(Vertex v, bool support, int handle_id);
  // Inserts `h` at `index` (0..#handles); its id must be unused and >= 0. Ids at or above
  // next_handle_id() advance it, so an id is never handed out twice.
  void insert_handle(int index, HandleState h);
  // Removes a handle that has no vertices left; returns it. InvalidInput otherwise.
  HandleState erase_handle(int id);
  void set_parameters(const EditParameters& p);  // normalized(p)
  // Validates (HandleState::transform) before changing anything.
  void set_transform(int id, const Manipulator& m, const std::optional<Eigen::Affine3d>& matrix);

  // --- derived ---
  std::vector<Vertex> support_vertices() const;  // sorted, handle vertices included
  // The affine map of handle `id` (pivot defaults to its rest centroid if unset).
  Eigen::Affine3d transform(int id, const Mesh& rest) const;
  // Empty if the regions can be built, else what the user should do ("paint a support region",
  // "handle 2 has no vertices: paint it or delete it", the Regions message).
  std::string problem(const Mesh& rest) const;
  Regions regions(const Mesh& rest) const;  // throws InvalidInput as Regions does
  const BcmSettings& settings() const { return params_.settings; }  // order, smoothness, anisotropic

  // The edit: vertex-index selectors, handles in order, per movable handle the exact affine
  // map the editor evaluates as "matrix" (so deform() replays it bit for bit), and the
  // smoothness segments cut to the smoothness band (segments left empty are dropped: they do
  // nothing, and an edit file refuses them).
  Edit to_edit(const Mesh& rest) const;
  // The state of an edit: handle i gets id first_id + i; a matrix handle keeps its matrix
  // under an identity manipulator, a manipulator handle keeps its manipulator; unset pivots
  // become the rest centroid. Throws InvalidInput for overlapping handles, indices outside
  // the mesh.
  static EditState from_edit(const Edit& edit, const Mesh& rest, int first_id = 0);

  // Exact equality of regions, handles (order, ids, transforms bitwise) and parameters.
  bool operator==(const EditState& o) const;

 private:
  std::vector<std::uint8_t> support_;
  std::vector<int> handle_;
  std::vector<HandleState> handles_;
  std::vector<int> counts_;  // vertices per handle, parallel to handles_
  EditParameters params_;
  int n_support_ = 0;
  int n_handle_vertices_ = 0;
  int next_id_ = 0;

  void check_vertex(Vertex v) const;
};

}  // namespace freeform::editor
