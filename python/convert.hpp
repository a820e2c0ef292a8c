#pragma once
// Between Python values and the library's: JSON documents (a spec given as a dict, results and
// metadata returned as dicts), arrays of directions, and brdfbake::Error raised as brdfbake.Error.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <optional>
#include <string>

namespace brdfbake::python {

namespace py = pybind11;

/// A Python value in the JSON spec's form (dict, list, tuple, str, int, float, bool, None; also
/// os.PathLike as its string and numpy scalars and arrays as their values) as JSON. Throws
/// Error(InvalidInput) "<label>: <json path>: ..." for anything else, a key that is not a string, a
/// NaN or infinite number, an integer beyond 64 bits, or nesting deeper than kMaxJsonDepth.
nlohmann::json jsonFromPython(py::handle value, const std::string& label);

/// JSON as Python: dict (keys in the document's order), list, str, int, float, bool, None.
py::object pythonFromJson(const nlohmann::json& value);
py::object pythonFromJson(const nlohmann::ordered_json& value);

/// The Python exception class for `kind` (brdfbake.InvalidInputError, ...), from brdfbake._errors.
/// parse(text) (a library parse* function), its error naming the keyword argument:
/// "texel_format: texel format must be one of ...".
template <class Parse>
auto parseNamed(const char* keyword, const std::string& text, Parse parse) {
  try {
    return parse(text);
  } catch (const Error& e) {
    throw Error(e.kind(), std::string(keyword) + ": " + e.what());
  }
}

py::object errorClass(Error::Kind kind);
/// "invalid_argument", "invalid_input", "io", "resource", "numerical".
const char* kindName(Error::Kind kind);

/// Directions given as an (N, 3) array (or one as a (3,) array), as float64 in C order. `single` is
/// true for a (3,) array. Throws Error(InvalidArgument) naming `name` for another shape or for
/// values that are not numbers, and, when `unit` is set, "<name>[i]: ..." for a row that is not
/// finite or is zero.
struct Directions {
  py::array_t<double, py::array::c_style | py::array::forcecast> array;
  std::size_t count = 0;
  bool single = false;

  Vec3 operator[](std::size_t i) const {
    const double* p = array.data() + 3 * i;
    return {p[0], p[1], p[2]};
  }
};
Directions directionsFromPython(py::handle value, const std::string& name);

/// Throws Error(InvalidArgument) "<name>[i]: a direction must be finite and non-zero, got (x, y, z)"
/// for the first such row.
void requireDirections(const Directions& directions, const std::string& name);

/// An (N, width) float64 array to fill without the GIL, or (width,) when `single`.
py::array_t<double> resultRows(std::size_t count, std::size_t width, bool single);

}  // namespace brdfbake::python
