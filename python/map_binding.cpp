// brdfbake.Map and brdfbake.read_map: any output of bake or prefilter read back, its pixels as a
// numpy array and its lookups vectorised (what `brdfbake sample` and `info` do, output/baked_output.hpp).
#include <brdfbake/io/image_io.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "convert.hpp"

namespace brdfbake::python {

namespace {

constexpr const char* kMapDoc = R"(An output of bake or prefilter read back, as a renderer reads it.

kind is "map" (sphere, paraboloid, cube cross or lat-long), "radial_profile", "elevation_stack",
"fresnel_table" or "sh_irradiance". sample() looks values up as `brdfbake sample` does (bilinear, as a
GPU filters); pixels holds the texels; metadata the map's brdfbake metadata (the spec it was made from).
Conventions (frames, row 0 at the top, alpha = coverage): docs/conventions.md.)";

constexpr const char* kSampleDoc = R"(Looks the output up at directions, as `brdfbake sample` does.

dirs: an (N, 3) array of lookup directions in the map's frame (any length but 0; eye space for sphere
maps: +z towards the viewer), or one direction as a (3,) array. The direction is the reflected direction
r, or the normal n for irradiance maps (indexed_by_normal).
cos_view: n.v, needed by elevation stacks and Fresnel tables and refused by the other kinds. A Fresnel
table takes no directions (dirs=None).
Returns an (N, 4) float64 array of R, G, B, A (alpha: the map's coverage), or (4,) for one direction.
The lookups run in parallel without the GIL.)";

constexpr const char* kReadMapDoc = R"(Reads any output of bake or prefilter (what `brdfbake sample` and `info` read).

path: a map (.exr, .hdr, .tif, .png, .ktx2, .ktx, .dds), STEM.EXT of a cube written as six faces or of an
elevation stack, a 1-D radial profile or Fresnel table, or an SH irradiance JSON.
from_: the parameterization of a plain image without brdfbake metadata: sphere | paraboloid | cube | latlong.
mip_level: the mip level of a map, faces or stack (STEM_mipK.EXT or a level of a MIP-mapped file).
Raises brdfbake.IoError for a missing file and brdfbake.InvalidInputError naming the file for one that
is no output.)";

// The value of `key` in the output's description, or None.
py::object described(const OpenedMap& map, const char* key) {
  const nlohmann::json description = map.output->describe();
  if (!description.contains(key)) return py::none();
  return pythonFromJson(description[key]);
}

py::array_t<float> imageArray(const Image& image) {
  py::array_t<float> array({image.height(), image.width(), 4});
  std::memcpy(array.mutable_data(), image.data(), sizeof(float) * 4 * image.width() * image.height());
  return array;
}

// Kinds other than Map: each file's image, read again (a copy); stacks as (K, H, W, 4).
py::object readPixels(const OpenedMap& map) {
  const BakedOutput& output = *map.output;
  if (output.kind() == OutputKind::ShIrradiance) return py::none();
  std::vector<Image> images;
  {
    const py::gil_scoped_release release;
    const int level = output.kind() == OutputKind::ElevationStack ? map.source.mipLevel : 0;
    for (const auto& file : output.files()) images.push_back(readImage(file, level));
  }
  if (output.kind() != OutputKind::ElevationStack) return imageArray(images.front());
  py::list slices;
  for (const auto& image : images) slices.append(imageArray(image));
  return py::module_::import("numpy").attr("stack")(slices);
}

// A Map's texels without a copy: a read-only view whose base keeps the Map alive.
py::object pixels(const py::object& self) {
  OpenedMap& map = self.cast<OpenedMap&>();
  py::object array;
  if (const MapFile* file = map.output->map()) {
    const Image& image = file->image;
    const auto channel = static_cast<py::ssize_t>(sizeof(float));
    array = py::array(py::dtype::of<float>(), {image.height(), image.width(), 4},
                      {channel * 4 * image.width(), channel * 4, channel}, image.data(), self);
  } else {
    if (!map.pixelsRead) map.pixelsRead = readPixels(map);
    array = map.pixelsRead;
  }
  if (!array.is_none()) array.attr("setflags")(py::arg("write") = false);
  return array;
}

py::object sample(const OpenedMap& map, const py::object& dirs, std::optional<double> cosView) {
  const BakedOutput& output = *map.output;
  OutputSource source = map.source;
  source.cosView = cosView;
  source.checkCosView(output);
  if (!output.usesDirection()) {
    if (!dirs.is_none()) {
      throw Error(Error::Kind::InvalidArgument, "dirs: a Fresnel table is a function of n.v alone: give cos_view only");
    }
    const Rgba v = output.lookup(Vec3::UnitZ(), cosView);
    py::array_t<double> value(4);
    for (int c = 0; c < 4; ++c) value.mutable_at(c) = v[c];
    return value;
  }
  if (dirs.is_none()) {
    throw Error(Error::Kind::InvalidArgument, "dirs: a " + std::string(toString(output.kind())) +
                                                  " is looked up at directions: give an (N, 3) array");
  }
  const Directions directions = directionsFromPython(dirs, "dirs");
  requireDirections(directions, "dirs");
  py::array_t<double> values = resultRows(directions.count, 4, directions.single);
  double* out = values.mutable_data();
  {
    const py::gil_scoped_release release;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, directions.count, 4096), [&](const auto& rows) {
      for (std::size_t i = rows.begin(); i < rows.end(); ++i) {
        const Rgba v = output.lookup(directions[i], cosView);
        for (int c = 0; c < 4; ++c) out[4 * i + c] = v[c];
      }
    });
  }
  return values;
}

std::string mapRepr(const OpenedMap& map) {
  const nlohmann::json d = map.output->describe();
  std::string text = "<brdfbake.Map " + d.value("kind", std::string());
  if (d.contains("parameterization")) text += " " + d["parameterization"].get<std::string>();
  if (d.contains("resolution")) text += " " + d["resolution"].dump();
  return text + (map.source.path.empty() ? " in memory>" : " '" + map.source.path.string() + "'>");
}

// Every mip level of a map in memory (copies), or the pixels of one read back.
py::list levels(const py::object& self) {
  const OpenedMap& map = self.cast<const OpenedMap&>();
  py::list out;
  if (map.levels.empty()) {
    out.append(pixels(self));
    return out;
  }
  for (const Image& level : map.levels) out.append(imageArray(level));
  return out;
}

// Writes a map in memory to `path` (and `more`), as the job that made it writes its outputs.
std::vector<std::filesystem::path> save(OpenedMap& map, const std::filesystem::path& path,
                                        const std::vector<std::filesystem::path>& more,
                                        const std::optional<std::string>& texelFormat, bool faces, bool tiled) {
  if (!map.writer) {
    throw Error(Error::Kind::InvalidArgument, "save: this map was read from " + map.source.path.string() +
                                                  "; copy the file, or resample it with `brdfbake convert`");
  }
  MapOutputs outputs;
  outputs.files = {path};
  outputs.files.insert(outputs.files.end(), more.begin(), more.end());
  outputs.layout = faces ? CubeLayout::Faces : CubeLayout::Cross;
  outputs.mipLayout = tiled ? MipLayout::Tiled : MipLayout::Files;
  if (texelFormat) outputs.texelFormat = parseNamed("texel_format", *texelFormat, parseTexelFormat);
  MapWriteReport written;
  try {
    const py::gil_scoped_release release;
    written = map.writer(outputs);
  } catch (const Error& e) {
    if (e.field().empty()) throw;
    throw Error(e.kind(), (e.field() == "outputs" ? std::string("path") : e.field()) + ": " + e.problem());
  }
  map.written = written.files;
  return written.files;
}

}  // namespace

std::shared_ptr<OpenedMap> mapInMemory(std::vector<Image> levels, const MapInfo& info, const nlohmann::json& entry,
                                       std::function<MapWriteReport(const MapOutputs&)> writer) {
  auto map = std::make_shared<OpenedMap>();
  map->output = std::make_shared<const BakedOutput>(BakedOutput::fromMap(levels.front(), info));
  map->levels = std::move(levels);
  map->result = pythonFromJson(entry);
  map->writer = std::move(writer);
  return map;
}

std::shared_ptr<OpenedMap> openMap(const OutputSource& source) {
  auto map = std::make_shared<OpenedMap>();
  map->source = source;
  const py::gil_scoped_release release;
  map->output = std::make_shared<const BakedOutput>(source.open("from_"));
  return map;
}

void bindMaps(py::module_& module) {
  py::class_<OpenedMap, std::shared_ptr<OpenedMap>>(module, "Map", kMapDoc)
      .def_property_readonly(
          "path",
          [](const OpenedMap& m) -> py::object {
            if (m.source.path.empty()) return py::none();
            return py::cast(m.source.path);
          },
          "The path it was read from or written to; None for a map only in memory.")
      .def_property_readonly(
          "kind", [](const OpenedMap& m) { return std::string(toString(m.output->kind())); },
          "map | radial_profile | elevation_stack | fresnel_table | sh_irradiance.")
      .def_property_readonly(
          "parameterization",
          [](const OpenedMap& m) {
            py::object p = described(m, "parameterization");
            if (p.is_none() && m.output->metadata().is_object() && m.output->metadata().contains("parameterization"))
              p = pythonFromJson(m.output->metadata()["parameterization"]);
            return p;
          },
          "sphere | paraboloid | cube | latlong for maps and stacks; profile, fresnel_table; None for SH.")
      .def_property_readonly(
          "resolution", [](const OpenedMap& m) { return described(m, "resolution"); },
          "The map's resolution N (texels per side, hemisphere, face or rows), or None.")
      .def_property_readonly(
          "metadata", [](const OpenedMap& m) { return pythonFromJson(m.output->metadata()); },
          "The brdfbake metadata (a dict): parameterization, resolution, convention_version, the spec it was made "
          "from; of slice 0 for a stack, of face +x for six faces.")
      .def_property_readonly(
          "files", [](const OpenedMap& m) { return m.output->files().empty() ? m.written : m.output->files(); },
          "Every file read, or written for a map made in memory ([] until it is saved).")
      .def_property_readonly(
          "uses_cos_view", [](const OpenedMap& m) { return m.output->usesCosView(); },
          "True for elevation stacks and Fresnel tables, which sample() reads at cos_view.")
      .def_property_readonly(
          "indexed_by_normal", [](const OpenedMap& m) { return m.output->indexedByNormal(); },
          "True if the lookup direction is the normal n (irradiance), not the reflected direction r.")
      .def_property_readonly(
          "eye_space", [](const OpenedMap& m) { return m.output->eyeSpace(); },
          "True for sphere maps and profiles about the view: the view is +z.")
      .def_property_readonly("pixels", &pixels,
                             "The texels, float32, read-only, row 0 at the top: (H, W, 4) RGBA, a view without a copy "
                             "for maps (a cube as its cross); a copy for profiles and Fresnel tables (1, N, 4) and "
                             "stacks (slices, H, W, 4); None for SH irradiance.")
      .def_property_readonly(
          "result", [](const OpenedMap& m) { return m.result; },
          "For a Map made by prefilter(): its entry as `brdfbake prefilter --json` prints it (files, method, error "
          "estimate); else None.")
      .def(
          "describe", [](const OpenedMap& m) { return pythonFromJson(m.output->describe()); },
          "What `brdfbake info` says of it: kind, files, size, parameterization, how to look it up.")
      .def("sample", &sample, py::arg("dirs") = py::none(), py::arg("cos_view") = py::none(), kSampleDoc)
      .def_property_readonly("levels", &levels,
                             "Every mip level as an (H, W, 4) float32 array (copies): a chain's or the solid-angle "
                             "mip chain's levels for a map in memory, [pixels] for one read back.")
      .def("save", &save, py::arg("path"), py::arg("more") = std::vector<std::filesystem::path>{}, py::kw_only(),
           py::arg("texel_format") = py::none(), py::arg("faces") = false, py::arg("tiled") = false,
           "Writes a map made in memory (matcap, prefilter) to path (and each of more), its format by the "
           "extension, as the tool writes it; returns every file written.")
      .def("__repr__", &mapRepr);

  module.def(
      "read_map",
      [](const std::filesystem::path& path, std::optional<std::string> from, int mipLevel) {
        OutputSource source;
        source.path = path;
        if (from) source.from = parseNamed("from_", *from, parseParameterizationKind);
        source.mipLevel = mipLevel;
        return openMap(source);
      },
      py::arg("path"), py::kw_only(), py::arg("from_") = py::none(), py::arg("mip_level") = 0, kReadMapDoc);
}

}  // namespace brdfbake::python
