#include "convert.hpp"

#include <brdfbake/io/json_text.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <vector>

namespace brdfbake::python {

namespace {

std::string typeName(py::handle value) { return py::str(py::type::handle_of(value).attr("__name__")); }

std::string shortRepr(py::handle value) {
  std::string text = py::repr(value);
  return text.size() > 60 ? text.substr(0, 57) + "..." : text;
}

// Walks a Python value, keeping its JSON path for messages.
class JsonConverter {
 public:
  explicit JsonConverter(const std::string& label)
      : label_(label),
        os_(py::module_::import("os")),
        mapping_(py::module_::import("collections.abc").attr("Mapping")),
        numpy_(py::module_::import("numpy")) {}

  nlohmann::json convert(py::handle value, const std::string& path, int depth) {
    PyObject* p = value.ptr();
    if (value.is_none()) return nullptr;
    if (PyBool_Check(p)) return p == Py_True;
    if (PyLong_Check(p)) return integer(value, path);
    if (PyFloat_Check(p)) {
      const double x = PyFloat_AsDouble(p);
      if (!std::isfinite(x)) fail(path, "must be a finite number, got " + shortRepr(value));
      return x;
    }
    if (PyUnicode_Check(p)) return text(value, path);
    if (depth >= kMaxJsonDepth) fail(path, "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    if (PyDict_Check(p) || py::isinstance(value, mapping_)) return object(value, path, depth);
    if (PyList_Check(p) || PyTuple_Check(p)) {
      nlohmann::json array = nlohmann::json::array();
      std::size_t i = 0;
      for (py::handle item : value) array.push_back(convert(item, path + "[" + std::to_string(i++) + "]", depth + 1));
      return array;
    }
    if (py::isinstance(value, os_.attr("PathLike"))) return convert(os_.attr("fsdecode")(value), path, depth);
    if (py::isinstance(value, numpy_.attr("ndarray"))) return convert(value.attr("tolist")(), path, depth);
    if (py::isinstance(value, numpy_.attr("generic"))) return convert(value.attr("item")(), path, depth);
    fail(path, "a " + typeName(value) + " is not a JSON value (dict, list, str, int, float, bool or None)");
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw Error(Error::Kind::InvalidInput, label_ + ": " + (path.empty() ? "the document" : path) + ": " + message);
  }

  nlohmann::json integer(py::handle value, const std::string& path) const {
    int overflow = 0;
    const long long x = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow == 0) return x;
    if (overflow > 0) {
      const unsigned long long u = PyLong_AsUnsignedLongLong(value.ptr());
      if (!PyErr_Occurred()) return u;
      PyErr_Clear();
    }
    fail(path, "the integer " + shortRepr(value) + " does not fit 64 bits");
  }

  std::string text(py::handle value, const std::string& path) const {
    Py_ssize_t size = 0;
    const char* utf8 = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
    if (!utf8) {
      PyErr_Clear();
      fail(path, "the string " + shortRepr(value) + " is not valid Unicode");
    }
    if (std::memchr(utf8, '\0', static_cast<std::size_t>(size)))  // as in JSON text (io/json_text.cpp)
      fail(path, "contains a NUL character (\\u0000), which no name or value may hold");
    return {utf8, static_cast<std::size_t>(size)};
  }

  nlohmann::json object(py::handle value, const std::string& path, int depth) {
    nlohmann::json object = nlohmann::json::object();
    for (py::handle item : value.attr("items")()) {
      const py::tuple pair = py::reinterpret_borrow<py::tuple>(item);
      if (!PyUnicode_Check(pair[0].ptr())) fail(path, "the key " + shortRepr(pair[0]) + " is not a string");
      const std::string key = text(pair[0], path);
      object[key] = convert(pair[1], path.empty() ? key : path + "." + key, depth + 1);
    }
    return object;
  }

  const std::string& label_;
  py::module_ os_;
  py::object mapping_;
  py::module_ numpy_;
};

// UTF-8 from the library as str; bytes that are not UTF-8 (a file name) kept as surrogate escapes.
py::str decoded(const std::string& text) {
  PyObject* s = PyUnicode_DecodeUTF8(text.data(), static_cast<Py_ssize_t>(text.size()), "surrogateescape");
  if (!s) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(s);
}

template <class Json>
py::object toPython(const Json& value) {
  using Type = nlohmann::json::value_t;
  switch (value.type()) {
    case Type::boolean:
      return py::bool_(value.template get<bool>());
    case Type::number_integer:
      return py::int_(value.template get<std::int64_t>());
    case Type::number_unsigned:
      return py::int_(value.template get<std::uint64_t>());
    case Type::number_float:
      return py::float_(value.template get<double>());
    case Type::string:
      return decoded(value.template get_ref<const std::string&>());
    case Type::array: {
      py::list list;
      for (const auto& item : value) list.append(toPython(item));
      return list;
    }
    case Type::object: {
      py::dict dict;
      for (const auto& [key, item] : value.items()) dict[decoded(key)] = toPython(item);
      return dict;
    }
    default:
      return py::none();
  }
}

}  // namespace

nlohmann::json jsonFromPython(py::handle value, const std::string& label) {
  JsonConverter converter(label);
  return converter.convert(value, "", 0);
}

py::object pythonFromJson(const nlohmann::json& value) { return toPython(value); }
py::object pythonFromJson(const nlohmann::ordered_json& value) { return toPython(value); }

const char* kindName(Error::Kind kind) {
  switch (kind) {
    case Error::Kind::InvalidArgument:
      return "invalid_argument";
    case Error::Kind::InvalidInput:
      return "invalid_input";
    case Error::Kind::Io:
      return "io";
    case Error::Kind::Resource:
      return "resource";
    case Error::Kind::Numerical:
      return "numerical";
  }
  return "invalid_argument";
}

py::object errorClass(Error::Kind kind) {
  return py::module_::import("brdfbake._errors").attr("error_class")(kindName(kind));
}

Directions directionsFromPython(py::handle value, const std::string& name) {
  Directions d;
  d.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!d.array) {
    throw Error(Error::Kind::InvalidArgument,
                name + ": expected an (N, 3) array of directions (numbers), got a " + typeName(value));
  }
  const py::ssize_t dims = d.array.ndim();
  if (dims == 1 && d.array.shape(0) == 3) {
    d.count = 1;
    d.single = true;
  } else if (dims == 2 && d.array.shape(1) == 3) {
    d.count = static_cast<std::size_t>(d.array.shape(0));
  } else {
    std::ostringstream shape;
    for (py::ssize_t i = 0; i < dims; ++i) shape << (i ? ", " : "") << d.array.shape(i);
    throw Error(Error::Kind::InvalidArgument, name + ": expected an (N, 3) array of directions, got shape (" +
                                                  shape.str() + (dims == 1 ? ",)" : ")"));
  }
  return d;
}

void requireDirections(const Directions& directions, const std::string& name) {
  for (std::size_t i = 0; i < directions.count; ++i) {
    const Vec3 d = directions[i];
    if (d.allFinite() && d.norm() > 0.0) continue;
    std::ostringstream text;
    text << (directions.single ? name : name + "[" + std::to_string(i) + "]")
         << ": a direction must be finite and non-zero, got (" << d.x() << ", " << d.y() << ", " << d.z() << ")";
    throw Error(Error::Kind::InvalidArgument, text.str());
  }
}

py::array_t<double> resultRows(std::size_t count, std::size_t width, bool single) {
  if (single) return py::array_t<double>(std::vector<py::ssize_t>{static_cast<py::ssize_t>(width)});
  return py::array_t<double>(
      std::vector<py::ssize_t>{static_cast<py::ssize_t>(count), static_cast<py::ssize_t>(width)});
}

}  // namespace brdfbake::python
