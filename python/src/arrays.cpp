// numpy in and out: any real dtype and any strides are converted (never reinterpreted); a
// wrong kind of data is a TypeError, a wrong shape a ValueError, both naming the argument.
#include "bindings.h"

#include "freeform/common/error.h"

#include <climits>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace freeform::python {
namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// `obj` as an array of real numbers (kind f, i, u; integers only when `integer`).
py::array real_array(py::handle obj, const std::string& name, bool integer) {
  py::array a = py::array::ensure(obj);
  const char* what = integer ? "integers" : "real numbers";
  if (!a) throw py::type_error(name + " must be an array of " + what + ", got " + std::string(py::str(obj.get_type())));
  const char kind = a.dtype().kind();
  const bool ok = kind == 'i' || kind == 'u' || (!integer && kind == 'f') || (integer && a.size() == 0 && kind == 'f');
  if (!ok)
    throw py::type_error(name + " must be an array of " + what + ", got dtype " + std::string(py::str(a.dtype())));
  return a;
}

void require_shape(const py::array& a, const std::string& name, const char* expected, py::ssize_t rows, py::ssize_t cols) {
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || a.shape(1) != cols)
    throw py::value_error(name + " must have shape " + expected + ", got " + shape_of(a));
}

template <class T>
void copy_faces(const py::array& a, const std::string& name, std::vector<Tri>& out) {
  const auto c = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!c) throw py::error_already_set();
  const T* p = c.data();
  for (std::size_t f = 0; f < out.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const T v = p[3 * f + k];
      bool bad = v > static_cast<T>(INT_MAX);
      if constexpr (std::is_signed_v<T>) bad = bad || v < static_cast<T>(INT_MIN);
      if (bad)
        throw InvalidInput(name + ": face " + std::to_string(f) + " references vertex " + std::to_string(v) +
                           ", which is out of range");
      out[f][k] = static_cast<int>(v);
    }
}

}  // namespace

std::vector<Vec3> to_positions(py::handle obj, const char* name) {
  const py::array a = real_array(obj, name, false);
  require_shape(a, name, "(n, 3)", -1, 3);
  const auto c = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!c) throw py::error_already_set();
  std::vector<Vec3> out(static_cast<std::size_t>(c.shape(0)));
  const double* p = c.data();
  for (Vec3& v : out) v = Vec3(p[0], p[1], p[2]), p += 3;
  return out;
}

std::vector<Tri> to_faces(py::handle obj, const char* name) {
  const py::array a = real_array(obj, name, true);
  require_shape(a, name, "(m, 3)", -1, 3);
  std::vector<Tri> out(static_cast<std::size_t>(a.shape(0)));
  if (a.dtype().kind() == 'u' && a.dtype().itemsize() == 8)
    copy_faces<std::uint64_t>(a, name, out);
  else
    copy_faces<std::int64_t>(a, name, out);
  return out;
}

void to_transforms(py::handle obj, int n, Eigen::Affine3d* out, const char* name) {
  const auto read = [&](py::handle item, const std::string& item_name, Eigen::Affine3d& t) {
    const py::array a = real_array(item, item_name, false);
    require_shape(a, item_name, "(4, 4)", 4, 4);
    const auto c = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!c) throw py::error_already_set();
    const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> m(c.data());
    if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0)
      throw InvalidInput(item_name + ": the last row must be 0 0 0 1 (an affine map)");
    t.matrix() = m;
  };
  if (py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).ndim() == 3) {
    const py::array a = real_array(obj, name, false);
    if (a.shape(0) != n || a.shape(1) != 4 || a.shape(2) != 4)
      throw py::value_error(std::string(name) + " must have shape (" + std::to_string(n) + ", 4, 4) (one matrix per movable handle), got " + shape_of(a));
    for (int i = 0; i < n; ++i) read(a[py::int_(i)], std::string(name) + "[" + std::to_string(i) + "]", out[i]);
    return;
  }
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
    throw py::type_error(std::string(name) + " must be a list of 4x4 arrays (one per movable handle), got " +
                         std::string(py::str(obj.get_type())));
  const auto seq = py::reinterpret_borrow<py::sequence>(obj);
  if (seq.size() != static_cast<std::size_t>(n))
    throw py::value_error(std::string(name) + " has " + std::to_string(seq.size()) + " entries, the solver has " +
                          std::to_string(n) + " movable handles (pass one 4x4 matrix per movable handle)");
  for (int i = 0; i < n; ++i) read(seq[static_cast<std::size_t>(i)], std::string(name) + "[" + std::to_string(i) + "]", out[i]);
}

std::string to_path(py::handle obj, const char* name) {
  if (!PyUnicode_Check(obj.ptr()) && !PyBytes_Check(obj.ptr()) && !py::hasattr(obj, "__fspath__"))
    throw py::type_error(std::string(name) + " must be a str, bytes or os.PathLike, got " + std::string(py::str(obj.get_type())));
  return py::module_::import("os").attr("fsdecode")(obj).cast<std::string>();
}

py::array_t<double> positions_array(const Vec3* data, std::size_t n) {
  py::array_t<double> a({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  if (n > 0) std::memcpy(a.mutable_data(), data, n * sizeof(Vec3));
  return a;
}

py::array_t<std::int64_t> faces_array(const std::vector<Tri>& faces) {
  py::array_t<std::int64_t> a({static_cast<py::ssize_t>(faces.size()), py::ssize_t{3}});
  std::int64_t* p = a.mutable_data();
  for (const Tri& f : faces)
    for (int v : f) *p++ = v;
  return a;
}

py::array_t<double> matrix_array(const Eigen::Affine3d& t) {
  py::array_t<double> a({py::ssize_t{4}, py::ssize_t{4}});
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(a.mutable_data()) = t.matrix();
  return a;
}

py::array_t<std::int64_t> vertex_array(const std::vector<Vertex>& vertices) {
  py::array_t<std::int64_t> a(static_cast<py::ssize_t>(vertices.size()));
  std::int64_t* p = a.mutable_data();
  for (Vertex v : vertices) *p++ = v.idx();
  return a;
}

}  // namespace freeform::python
