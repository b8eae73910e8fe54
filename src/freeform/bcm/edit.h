// One edit as data (the resolved form of an edit file, docs/edit-format.md) and the one-shot
// deform(). The JSON parsing and selector resolution live in edit_file.h.
#pragma once

#include "freeform/bcm/bcm_solver.h"
#include "freeform/bcm/manipulator.h"
#include "freeform/bcm/settings.h"
#include "freeform/mesh/mesh.h"

#include <optional>
#include <vector>

namespace freeform {

struct EditHandle {
  std::vector<Vertex> vertices;
  bool fixed = false;                    // immovable handle
  Manipulator manipulator;               // used unless `matrix` is set
  std::optional<Eigen::Affine3d> matrix; // a general affine map given as a 4x4 matrix
};

struct Edit {
  BcmSettings settings;
  std::vector<Vertex> support;
  std::vector<EditHandle> handles;
  bool anisotropic = false;      // anisotropic bending (docs/anisotropic.md): see solver_settings
  bool multiresolution = true;   // detail-preserving editing (docs/multires.md); the default
};

// The solver settings of the edit: `settings` with anisotropic = settings.anisotropic || anisotropic.
BcmSettings solver_settings(const Edit& edit);

// The affine map of each movable handle (default pivot: the handle centroid).
std::vector<Eigen::Affine3d> edit_transforms(const Edit& edit, const BcmSolver& solver);

// Applies the edit to a copy of the mesh (vertex order and faces kept). Fills stats if given.
// With edit.multiresolution the detail inside the support is kept (MultiresSolver).
// Implemented in freeform_multires (src/freeform/multires/deform.cpp): link it to call this.
Mesh deform(const Mesh& mesh, const Edit& edit, BcmStats* stats = nullptr);

}  // namespace freeform
