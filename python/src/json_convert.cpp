// JSON <-> Python data, for edit dicts (Edit.from_dict / to_dict) and reports (solver.stats).
// Python ints stay integers and floats stay doubles, so a dict parses exactly like the edit file
// with the same content, and a NaN reaches the edit reader (which names its key).
#include "bindings.h"

#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"

#include <cstdint>

namespace freeform::python {
namespace {

using json_messages::index_path;
using json_messages::key_path;

// Deeper than any edit needs, and far below what the C stack holds: a list nested 100,000 deep
// (or one that contains itself) is refused instead of crashing the interpreter.
constexpr int kMaxDepth = 1000;

std::string where(const std::string& path, const char* preposition = " at ") {
  if (path.empty()) return {};
  constexpr std::size_t kShown = 60;
  return preposition + std::string("\"") + (path.size() > kShown ? path.substr(0, kShown) + "..." : path) + "\"";
}

// UTF-8 of a Python str; a lone surrogate (not encodable) is named instead of pybind11's
// generic cast error.
std::string utf8(py::handle s, const std::string& name, const std::string& what, const std::string& path) {
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(s.ptr(), &size);
  if (!data) {
    PyErr_Clear();
    throw InvalidInput(name + ": " + what + " " + std::string(py::repr(s)) +
                          " is not valid Unicode (a lone surrogate?)" + where(path));
  }
  return {data, static_cast<std::size_t>(size)};
}

Json from_int(py::handle obj) {
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(obj.ptr(), &overflow);
  if (overflow == 0) {
    if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
    return v;
  }
  if (overflow > 0) {
    const unsigned long long u = PyLong_AsUnsignedLongLong(obj.ptr());
    if (!PyErr_Occurred()) return u;
    PyErr_Clear();
  }
  return obj.cast<double>();  // beyond 64 bits: a double, as JSON text would give
}

Json convert(py::handle obj, const std::string& name, const std::string& path, int depth) {
  if (depth > kMaxDepth)
    throw InvalidInput(name + ": nested too deeply (more than " + std::to_string(kMaxDepth) + " levels)" +
                          where(path));
  if (obj.is_none()) return nullptr;
  if (PyBool_Check(obj.ptr())) return obj.cast<bool>();
  if (PyLong_Check(obj.ptr())) return from_int(obj);
  if (PyFloat_Check(obj.ptr())) return obj.cast<double>();
  if (PyUnicode_Check(obj.ptr())) return utf8(obj, name, "string", path);
  if (PyDict_Check(obj.ptr())) {
    Json out = Json::object();
    for (auto [k, v] : py::reinterpret_borrow<py::dict>(obj)) {
      if (!PyUnicode_Check(k.ptr()))
        throw py::type_error(name + ": keys must be strings, got " + std::string(py::repr(k)) + where(path, " in "));
      const std::string key = utf8(k, name, "key", path);
      out[key] = convert(v, name, key_path(path, key), depth + 1);
    }
    return out;
  }
  if (PyList_Check(obj.ptr()) || PyTuple_Check(obj.ptr())) {
    Json out = Json::array();
    std::size_t i = 0;
    for (py::handle item : obj) out.push_back(convert(item, name, index_path(path, i++), depth + 1));
    return out;
  }
  const py::module_ np = py::module_::import("numpy");
  if (py::isinstance<py::array>(obj)) return convert(obj.attr("tolist")(), name, path, depth);
  if (py::isinstance(obj, np.attr("bool_"))) return obj.cast<bool>();
  if (py::isinstance(obj, np.attr("integer")))
    return convert(py::int_(py::reinterpret_borrow<py::object>(obj)), name, path, depth);
  if (py::isinstance(obj, np.attr("floating"))) return obj.cast<double>();
  throw py::type_error(name + ": cannot convert " + std::string(py::str(obj.get_type())) + " to JSON" + where(path));
}

}  // namespace

Json to_json(py::handle obj, const std::string& name) { return convert(obj, name, "", 0); }

py::object to_python(const Json& j) {
  switch (j.type()) {
    case Json::value_t::boolean: return py::bool_(j.get<bool>());
    case Json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case Json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case Json::value_t::number_float: return py::float_(j.get<double>());
    case Json::value_t::string: return py::str(j.get_ref<const std::string&>());
    case Json::value_t::array: {
      py::list out;
      for (const Json& v : j) out.append(to_python(v));
      return out;
    }
    case Json::value_t::object: {
      py::dict out;
      for (const auto& [k, v] : j.items()) out[py::str(k)] = to_python(v);
      return out;
    }
    default: return py::none();
  }
}

}  // namespace freeform::python
