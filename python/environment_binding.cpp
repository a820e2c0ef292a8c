// brdfbake.Environment: radiance loaded once (a file, or a numpy array in memory) and kept, with what
// shading under it prepares, for many matcaps, prefilters and IBL sets (env/environment.hpp).
#include <brdfbake/env/environment.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "bindings.hpp"
#include "convert.hpp"

namespace brdfbake::python {

namespace {

constexpr const char* kEnvironmentDoc = R"(Radiance over the sphere of directions, loaded or wrapped once and kept.

Environment(source, from_=None): source is an image file (EXR, HDR, ...; a cube as six files
STEM_posx.EXT ...: pass STEM.EXT) or a numpy array of radiance (H, W, 3) or (H, W, 4), float32 or
anything numpy casts to it, row 0 at the top. A file's parameterization comes from its brdfbake
metadata, else from_, else its shape (2:1 lat-long, 4:3 cube cross); an array is a lat-long image
unless from_ says otherwise (sphere | paraboloid | cube | latlong). The frame: y up, a lat-long
image's centre looking down -z (docs/conventions.md). Pass it to matcap(), prefilter() and ibl():
what they prepare from it (its bright texels, its mip pyramid) is kept for the next call.)";

// An (H, W, 3 or 4) array of radiance as a float RGBA image (alpha 1 where not given).
Image environmentImage(const py::object& value) {
  const auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!array || array.ndim() != 3 || (array.shape(2) != 3 && array.shape(2) != 4) || array.shape(0) < 1 ||
      array.shape(1) < 1) {
    std::ostringstream shape;
    if (array)
      for (py::ssize_t i = 0; i < array.ndim(); ++i) shape << (i ? ", " : "") << array.shape(i);
    throw Error(
        Error::Kind::InvalidArgument,
        "environment: expected an (H, 2H, 3) array of radiance (a lat-long image, row 0 at the top)" +
            (array ? ", got shape (" + shape.str() + ")" : ", got a " + std::string(py::str(value.get_type()))));
  }
  const int height = static_cast<int>(array.shape(0)), width = static_cast<int>(array.shape(1));
  const int channels = static_cast<int>(array.shape(2));
  Image image(width, height, Rgba::Ones());
  const float* in = array.data();
  float* out = image.data();
  for (std::size_t i = 0; i < static_cast<std::size_t>(width) * height; ++i) {
    for (int c = 0; c < channels; ++c) {
      const float v = in[i * channels + c];
      if (!std::isfinite(v)) {
        std::ostringstream text;
        text << "environment[" << i / width << ", " << i % width << ", " << c << "]: radiance must be finite, got "
             << v;
        throw Error(Error::Kind::InvalidArgument, text.str());
      }
      out[4 * i + c] = v;
    }
  }
  return image;
}

std::optional<ParameterizationKind> parameterizationArgument(const std::optional<std::string>& from) {
  if (!from) return std::nullopt;
  return parseNamed("from_", *from, parseParameterizationKind);
}

}  // namespace

std::shared_ptr<const Environment> environmentFromPython(const py::object& source,
                                                         const std::optional<std::string>& from) {
  if (py::isinstance<PythonEnvironment>(source)) {
    if (from) throw Error(Error::Kind::InvalidArgument, "from_: an Environment knows its parameterization");
    return source.cast<const PythonEnvironment&>().environment;
  }
  const std::optional<ParameterizationKind> kind = parameterizationArgument(from);
  if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__")) {
    const std::filesystem::path path = source.cast<std::filesystem::path>();
    require(!path.empty(), "environment: an empty path");
    const py::gil_scoped_release release;
    return std::make_shared<const Environment>(loadEnvironment(path, {kind}));
  }
  Image image = environmentImage(source);
  const py::gil_scoped_release release;
  return std::make_shared<const Environment>(
      makeEnvironment(std::move(image), kind.value_or(ParameterizationKind::LatLong), "environment array"));
}

void bindEnvironment(py::module_& module) {
  py::class_<PythonEnvironment>(module, "Environment", kEnvironmentDoc)
      .def(py::init([](const py::object& source, const std::optional<std::string>& from) {
             return PythonEnvironment{environmentFromPython(source, from)};
           }),
           py::arg("source"), py::arg("from_") = py::none())
      .def_property_readonly(
          "parameterization", [](const PythonEnvironment& e) { return std::string(toString(e.environment->kind())); },
          "sphere | paraboloid | cube | latlong.")
      .def_property_readonly(
          "resolution", [](const PythonEnvironment& e) { return e.environment->map->resolution(); },
          "Its resolution N (texels per side, hemisphere, face or rows).")
      .def_property_readonly(
          "source", [](const PythonEnvironment& e) { return e.environment->source; },
          "The file it was read from, or \"environment array\".")
      .def_property_readonly(
          "detection", [](const PythonEnvironment& e) { return e.environment->detection; },
          "How its parameterization was decided.")
      .def_property_readonly(
          "pixels",
          [](const py::object& self) {
            const Image& image = self.cast<const PythonEnvironment&>().environment->image;
            const auto channel = static_cast<py::ssize_t>(sizeof(float));
            py::array array(py::dtype::of<float>(), {image.height(), image.width(), 4},
                            {channel * 4 * image.width(), channel * 4, channel}, image.data(), self);
            array.attr("setflags")(py::arg("write") = false);
            return array;
          },
          "The radiance as held: (H, W, 4) float32, read-only, a view without a copy.")
      .def("__repr__", [](const PythonEnvironment& e) {
        return "<brdfbake.Environment " + std::string(toString(e.environment->kind())) + " " +
               std::to_string(e.environment->map->resolution()) + " '" + e.environment->source + "'>";
      });
}

}  // namespace brdfbake::python
