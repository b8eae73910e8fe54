// freeform.EditSolver (precompute once with the GIL released, progress and cancellation from
// Python; evaluate per frame) and the one-shot freeform.deform.
#include "bindings.h"

#include "freeform/common/error.h"
#include "freeform/common/parallel.h"
#include "freeform/edit/edit_report.h"
#include "freeform/edit/drag_session.h"
#include "freeform/edit/edit_solver.h"

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <exception>
#include <mutex>
#include <span>

namespace freeform::python {
namespace {

// Forwards Progress reports to a Python callable (stage, fraction) with the GIL held; an
// exception from it (or a pending Ctrl+C) cancels the precomputation and is re-raised after it.
struct ProgressBridge {
  explicit ProgressBridge(py::object f, double interval_ms = 0.0)
      : callback(std::move(f)), min_interval_ms(interval_ms) {}
  py::object callback;
  double min_interval_ms;  // checks closer than this are skipped (each takes the GIL)
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  std::atomic<bool> cancel{false};
  std::unique_ptr<py::error_already_set> error;
  std::exception_ptr cpp_error;

  Progress progress() {
    Progress p;
    p.cancel = &cancel;
    p.report = [this](std::string_view stage, double fraction) {
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double, std::milli>(now - last).count() < min_interval_ms) return;
      last = now;
      py::gil_scoped_acquire gil;
      if (error || cpp_error) return;
      try {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (!callback.is_none()) callback(std::string(stage), fraction);
      } catch (py::error_already_set& e) {
        error = std::make_unique<py::error_already_set>(std::move(e));
        cancel = true;
      } catch (...) {
        cpp_error = std::current_exception();
        cancel = true;
      }
    };
    return p;
  }
  void rethrow() {
    if (error) throw std::move(*error);
    if (cpp_error) std::rethrow_exception(cpp_error);
  }
};

// Runs f(progress) with the GIL released; the progress checks Python's signals every few
// milliseconds, so Ctrl-C stops a long nonlinear solve or settle within one iteration
// (KeyboardInterrupt, positions as before).
template <class F>
void interruptible(F&& f) {
  ProgressBridge bridge(py::none(), 10.0);
  {
    py::gil_scoped_release release;
    try {
      f(bridge.progress());
    } catch (...) {
      if (!bridge.error && !bridge.cpp_error) throw;
    }
  }
  bridge.rethrow();
}

class PySolver {
 public:
  PySolver(std::shared_ptr<Mesh> mesh, const PyEdit& edit, py::object progress) : mesh_(std::move(mesh)) {
    if (edit.n_vertices != mesh_->n_vertices())
      throw InvalidInput("the edit was resolved on a mesh with " + std::to_string(edit.n_vertices) +
                         " vertices, this mesh has " + std::to_string(mesh_->n_vertices()));
    if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
      throw py::type_error("progress must be None or a callable (stage, fraction), got " +
                           std::string(py::str(progress.get_type())));
    ProgressBridge bridge(std::move(progress));
    {
      py::gil_scoped_release release;
      try {
        solver_ = std::make_unique<EditSolver>(*mesh_, edit.edit, bridge.progress());
      } catch (...) {
        if (!bridge.error && !bridge.cpp_error) throw;
      }
    }
    bridge.rethrow();
    own_ = solver_->transforms(edit.edit);
    positions_ = mesh_->positions();
    // A first frame: stats and problems are always defined.
    interruptible([&](const Progress& p) { solver_->evaluate(own_, positions_, p); });
  }

  int n_movable() const { return solver_->n_movable(); }
  const EditSolver& solver() const { return *solver_; }
  std::shared_ptr<Mesh> mesh() const { return std::const_pointer_cast<Mesh>(mesh_); }
  const std::vector<Eigen::Affine3d>& own() const { return own_; }

  // n x 3 positions of a frame, a new array.
  py::array_t<double> evaluate(py::handle transforms) {
    Buffer buf;
    const std::span<const Eigen::Affine3d> t = read(transforms, buf);
    py::array_t<double> out({static_cast<py::ssize_t>(positions_.size()), py::ssize_t{3}});
    double* dst = out.mutable_data();
    interruptible([&](const Progress& progress) {
      const std::lock_guard lock(mutex_);
      drag_.reset();
      solver_->evaluate(t, positions_, progress);
      require_finite_frame(t);
      std::memcpy(dst, positions_.raw().data(), positions_.size() * sizeof(Vec3));
    });
    return out;
  }

  // Writes the touched rows of `out` (float64, n x 3, C-contiguous, writeable).
  void evaluate_into(py::handle out, py::handle transforms) {
    double* dst = output(out);
    Buffer buf;
    const std::span<const Eigen::Affine3d> t = read(transforms, buf);
    interruptible([&](const Progress& progress) {
      const std::lock_guard lock(mutex_);
      drag_.reset();
      solver_->evaluate(t, positions_, progress);
      require_finite_frame(t);
      copy_touched(dst);
    });
  }

  // An interactive frame (DragSession): the nonlinear model iterates on a worker thread and
  // the frame shows its newest iterate, moved by linear BCM's change when the transforms are
  // newer (never waits). settle: wait until it converged (or hit its cap) for these transforms.
  // Writes the touched rows of `out` like evaluate_into. Other frame methods end the session.
  py::dict drag_frame(py::handle out, py::handle transforms, bool settle) {
    double* dst = output(out);
    Buffer buf;
    const std::span<const Eigen::Affine3d> t = read(transforms, buf);
    DragFrame f;
    interruptible([&](const Progress& progress) {
      const std::lock_guard lock(mutex_);
      if (!drag_) drag_ = std::make_unique<DragSession>(*solver_);
      f = settle ? drag_->finish(t, positions_, progress) : drag_->frame(t, positions_);
      drag_state_ = f.state;
      copy_touched(dst);
    });
    py::dict d;
    d["written"] = f.written;
    d["predicted"] = f.predicted;
    d["settled"] = f.settled;
    d["iterations"] = f.state.iterations;
    d["residual"] = f.state.step;
    d["converged"] = f.settled && f.state.converged;
    return d;
  }

  // Seconds of `n` C++ evaluate() calls (no Python in the loop): the benchmark's reference.
  // With `copy`, each call also copies the touched rows to a private n x 3 array, as
  // evaluate_into does.
  py::array_t<double> time_evaluate(int n, py::handle transforms, bool copy) {
    if (n < 1) throw py::value_error("n must be >= 1");
    Buffer buf;
    const std::span<const Eigen::Affine3d> t = read(transforms, buf);
    py::array_t<double> seconds(n);
    double* dst = seconds.mutable_data();
    {
      py::gil_scoped_release release;
      const std::lock_guard lock(mutex_);
      drag_.reset();
      std::vector<double> out(copy ? 3 * positions_.size() : 0);
      for (int i = 0; i < n; ++i) {
        const auto start = std::chrono::steady_clock::now();
        solver_->evaluate(t, positions_);
        if (copy) copy_touched(out.data());
        dst[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
    }
    return seconds;
  }

  py::object stats() {
    Json report = {{"vertices", mesh_->n_vertices()}, {"faces", mesh_->n_faces()}};
    {
      py::gil_scoped_release release;
      const std::lock_guard lock(mutex_);
      report.update(edit_report(*solver_, solver_->last_timings(), solver_->problems(positions_),
                                drag_ ? &drag_state_ : nullptr));
    }
    return to_python(report);
  }

  py::dict problems() {
    EditProblems p;
    {
      py::gil_scoped_release release;
      const std::lock_guard lock(mutex_);
      p = solver_->problems(positions_);
    }
    py::dict d;
    d["ok"] = p.ok();
    d["non_finite"] = p.non_finite;
    d["first_non_finite"] = p.non_finite > 0 ? py::object(py::int_(p.first_non_finite.idx())) : py::none();
    d["folded_edges"] = p.folded_edges;
    d["flipped_triangles"] = p.detail.flipped;
    d["overlaps"] = p.detail.overlaps;
    return d;
  }

 private:
  // As deform: never a silent NaN. Only the touched rows are scanned; problems() (which also
  // counts folds) runs only to name the first bad vertex.
  void require_finite_frame(std::span<const Eigen::Affine3d> transforms) const {
    for (Vertex v : solver_->touched())
      if (!positions_[v].allFinite()) return require_finite(solver_->problems(positions_), transforms);
  }

  // Transforms of one call: on the stack for up to 8 movable handles (no allocation per frame).
  struct Buffer {
    std::array<Eigen::Affine3d, 8> small;
    std::vector<Eigen::Affine3d> large;
  };
  std::span<const Eigen::Affine3d> read(py::handle transforms, Buffer& buf) const {
    if (transforms.is_none()) return own_;
    const int n = n_movable();
    Eigen::Affine3d* p = buf.small.data();
    if (n > static_cast<int>(buf.small.size())) {
      buf.large.resize(static_cast<std::size_t>(n));
      p = buf.large.data();
    }
    to_transforms(transforms, n, p, "transforms");
    return {p, static_cast<std::size_t>(n)};
  }

  // `out` checked as a frame's destination: float64, n x 3, C-contiguous, writeable (never
  // converted, since it is written).
  double* output(py::handle out) const {
    if (!py::isinstance<py::array_t<double>>(out))
      throw py::type_error("out must be a float64 numpy array, got " +
                           std::string(py::str(py::isinstance<py::array>(out) ? out.attr("dtype") : out.get_type())));
    auto a = py::reinterpret_borrow<py::array>(out);
    if (a.ndim() != 2 || a.shape(0) != static_cast<py::ssize_t>(positions_.size()) || a.shape(1) != 3)
      throw py::value_error("out must have shape (" + std::to_string(positions_.size()) + ", 3), got " +
                            std::string(py::str(out.attr("shape"))));
    if (!(a.flags() & py::array::c_style) || !a.writeable())
      throw py::value_error("out must be C-contiguous and writeable (np.ascontiguousarray, or mesh.vertices)");
    return static_cast<double*>(a.mutable_data());
  }

  // The touched rows of positions_ to dst (n x 3), split across threads like the frame itself.
  void copy_touched(double* dst) const {
    const std::vector<Vertex>& touched = solver_->touched();
    const auto n = static_cast<std::ptrdiff_t>(touched.size());
    parallel_for(n, 8192, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
      for (std::ptrdiff_t i = lo; i < hi; ++i) {
        const Vec3& p = positions_[touched[static_cast<std::size_t>(i)]];
        double* row = dst + 3 * static_cast<std::ptrdiff_t>(touched[static_cast<std::size_t>(i)].idx());
        row[0] = p[0];
        row[1] = p[1];
        row[2] = p[2];
      }
    });
  }

  std::shared_ptr<const Mesh> mesh_;
  std::unique_ptr<EditSolver> solver_;
  std::vector<Eigen::Affine3d> own_;  // the edit's own transforms
  VertexData<Vec3> positions_;        // rest positions with the last frame's touched vertices
  std::mutex mutex_;                  // EditSolver::evaluate uses workspace: one frame at a time
  // Declared after solver_ (its worker uses it): destroyed first.
  std::unique_ptr<DragSession> drag_;
  NonlinearState drag_state_;         // of drag_'s last frame
};

}  // namespace

void bind_solver(py::module_& m) {
  py::class_<PySolver>(m, "EditSolver",
                       "The precomputed edit: the constructor does all sparse work once (GIL released), "
                       "evaluate(transforms) is the per-frame dense product.")
      .def(py::init([](std::shared_ptr<Mesh> mesh, const PyEdit& edit, py::object progress) {
             return std::make_unique<PySolver>(std::move(mesh), edit, std::move(progress));
           }),
           py::arg("mesh"), py::arg("edit"), py::arg("progress") = py::none(),
           "progress(stage, fraction) is called between stages; an exception raised from it cancels the "
           "precomputation and propagates. Raises Error (regions, settings), SolverError (factorization).")
      .def("evaluate", &PySolver::evaluate, py::arg("transforms") = py::none(),
           "Positions of all vertices (new n x 3 float64 array) for one 4x4 affine matrix per movable handle "
           "(a list, or an (m, 4, 4) array), applied to the rest positions; default: the edit's own.")
      .def("evaluate_into", &PySolver::evaluate_into, py::arg("out"), py::arg("transforms") = py::none(),
           "Like evaluate, but writes into `out` (float64, n x 3, C-contiguous) without allocating: only the "
           "rows of `touched` are written, the others keep what `out` holds (start from mesh.vertices).")
      .def(
          "frame",
          [](PySolver& self, py::handle out, py::handle transforms) { return self.drag_frame(out, transforms, false); },
          py::arg("out"), py::arg("transforms") = py::none(),
          "An interactive frame that never waits: the nonlinear model iterates on a worker thread and this shows "
          "its newest iterate (moved by linear BCM's change while the transforms are newer than it); call again "
          "while not settled to see it converge. Writes out like evaluate_into; returns {written (the shape "
          "changed), predicted, settled, iterations, residual, converged}. The linear model: evaluate_into.")
      .def(
          "settle",
          [](PySolver& self, py::handle out, py::handle transforms) { return self.drag_frame(out, transforms, true); },
          py::arg("out"), py::arg("transforms") = py::none(),
          "Like frame, but waits (GIL released) until the nonlinear model converged or hit its iteration cap "
          "for these transforms: the end of a drag.")
      .def("_time_evaluate", &PySolver::time_evaluate, py::arg("n"), py::arg("transforms") = py::none(),
           py::arg("copy") = false,
           "Seconds of each of n C++ evaluate() calls without Python in the loop (benchmarks); copy=True adds "
           "evaluate_into's copy of the touched rows.")
      .def_property_readonly("stats", &PySolver::stats,
                             "The report of the last frame as a dict: the keys of `freeform deform --report` "
                             "(counts, solver, timings_ms, residual, multiresolution, ...).")
      .def("problems", &PySolver::problems,
           "What is wrong with the last frame: non-finite positions, folded edges, flipped or flattened detail.")
      .def_property_readonly("mesh", &PySolver::mesh, "The Mesh the solver was built on (its rest positions).")
      .def_property_readonly("n_vertices", [](const PySolver& s) { return s.solver().n_vertices(); },
                             "Rows of a frame's positions.")
      .def_property_readonly("n_movable", &PySolver::n_movable, "Transforms per frame, in handle order.")
      .def_property_readonly("touched", [](const PySolver& s) { return vertex_array(s.solver().touched()); },
                             "(t,) int64 array: the vertices a frame writes (free and movable-handle vertices), sorted.")
      .def_property_readonly(
          "transforms",
          [](const PySolver& s) {
            py::list out;
            for (const Eigen::Affine3d& t : s.own()) out.append(matrix_array(t));
            return out;
          },
          "The edit's own transforms: a list of (4, 4) float64 arrays, one per movable handle.")
      .def(
          "handle_centroid",
          [](const PySolver& s, int movable) {
            if (movable < 0 || movable >= s.n_movable())
              throw py::index_error("movable handle " + std::to_string(movable) + " out of range (" +
                                    std::to_string(s.n_movable()) + " movable handles)");
            const Vec3 c = s.solver().handle_centroid(movable);
            return positions_array(&c, 1).attr("reshape")(3);
          },
          py::arg("movable"), "(3,) float64 array: the rest centroid of movable handle m (the default pivot).");

  m.def(
      "deform",
      [](const Mesh& mesh, const PyEdit& edit) {
        if (edit.n_vertices != mesh.n_vertices())
          throw InvalidInput("the edit was resolved on a mesh with " + std::to_string(edit.n_vertices) +
                             " vertices, this mesh has " + std::to_string(mesh.n_vertices()));
        Mesh out;
        {
          py::gil_scoped_release release;
          out = deform(mesh, edit.edit);
        }
        return positions_array(out.positions().raw().data(), out.positions().size());
      },
      py::arg("mesh"), py::arg("edit"),
      "The edited positions (n x 3 float64): EditSolver and one evaluate with the edit's own transforms. Raises "
      "SolverError on a non-finite result.");
}

}  // namespace freeform::python
