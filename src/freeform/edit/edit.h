// One edit as data (the resolved form of an edit file, docs/edit-format.md): the support, the
// handles with their transforms, the settings and the deformation model. edit_json.h reads and
// writes it; EditSolver (edit_solver.h) precomputes it.
#pragma once

#include "freeform/edit/manipulator.h"
#include "freeform/bcm/settings.h"
#include "freeform/mesh/mesh.h"
#include "freeform/nonlinear/nonlinear_solver.h"
#include "freeform/regions/regions.h"

#include <Eigen/Geometry>

#include <array>
#include <optional>
#include <string_view>
#include <vector>

namespace freeform {

// The deformation model EditSolver runs (docs/architecture.md says how to add one).
enum class Deformation {
  Linear,     // the paper's BCM: a precomputed basis, every frame one dense product
  Nonlinear,  // rotation-aware BCM (docs/nonlinear.md): iterations of back-substitutions
};
inline constexpr std::array<Deformation, 2> kDeformations = {Deformation::Linear, Deformation::Nonlinear};
std::string_view deformation_name(Deformation d);  // "linear", "nonlinear", as in edit files
std::optional<Deformation> deformation_from_name(std::string_view name);  // nullopt: no such model

struct EditHandle {
  std::vector<Vertex> vertices;
  bool movable = true;                    // false: immovable, acts like fixed surface (holes)
  Manipulator manipulator;                // used unless `matrix` is set
  std::optional<Eigen::Affine3d> matrix;  // a general affine map given as a 4x4 matrix
};

// An edit's settings: all of an edit file but its regions and transforms, in the one form every
// front end holds (the editor and its sessions, the CLI, Python, Blender). edit_json.h reads and
// writes them as edit-file keys; a new setting is added here and there (docs/architecture.md).
struct EditSettings {
  BcmSettings settings;  // order, boundary smoothness (with its segments), anisotropic bending
  bool multiresolution = true;  // detail-preserving editing (docs/multires.md); the default
  Deformation deformation = Deformation::Linear;
  NonlinearOptions nonlinear;  // iterations, tolerance and volume term of the nonlinear model
  // The linear model refuses a closed component held by movable handles only (nothing fixed):
  // its fill collapses onto the handles. true: solve it anyway.
  bool allow_unanchored = false;
  bool operator==(const EditSettings&) const = default;
};

struct Edit : EditSettings {
  std::vector<Vertex> support;
  std::vector<EditHandle> handles;
};

int n_movable(const Edit& edit);

// The Regions of an edit: its support and its handles in edit order. Isolated vertices (in no
// face) are left out of the support: they stay fixed (EditStats::isolated_ignored counts them).
// Throws InvalidInput as Regions does.
Regions edit_regions(const Mesh& mesh, const Edit& edit);

}  // namespace freeform
