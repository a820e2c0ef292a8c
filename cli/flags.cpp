#include "flags.hpp"

#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/files.hpp>

#include <algorithm>

namespace brdfbake::cli {

namespace fs = std::filesystem;

void addCommonFlags(CLI::App* command, CommonFlags& flags, Computes computes, const std::string& holds) {
  if (computes != Computes::Nothing) {
    command->add_option("--threads", flags.threads, "Worker threads (0 = every core)")
        ->default_val(0)
        ->check(CLI::Range(0, kMaxThreads));
  }
  if (computes == Computes::Maps) {
    command->add_flag("--allow-large", flags.allowLarge, "Allow maps over 8192^2 texels (1 GiB of float RGBA)");
  }
  command->add_flag("--json", flags.json, "Print a machine-readable report on stdout instead of text: " + holds);
  command->add_flag("--quiet", flags.quiet, "No progress, notes or 'wrote' lines: only errors (and a query's values)");
}

void printJsonOrText(const nlohmann::json& json, const std::string& text, const CommonFlags& flags, int indent) {
  if (!json.is_null()) {
    writeStdout(json.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  } else if (!flags.quiet) {
    writeStdout(printableMessage(text));
  }
}

Vec3 parseVec3(const std::string& text) {
  const auto bad = [&] {
    return Error(Error::Kind::InvalidArgument,
                 "expected three finite numbers X,Y,Z, got '" + shortenForMessage(text, 80) + "'");
  };
  std::vector<double> values;
  try {
    values = listOf(parseFiniteNumber)(text);
  } catch (const Error&) {
    throw bad();
  }
  if (values.size() != 3) throw bad();
  return {values[0], values[1], values[2]};
}

void addSourceOptions(CLI::App* command, OutputSource& source, bool cosView) {
  command->add_option("map", source.path, "Output of bake or prefilter (or a plain image with --from)")->required();
  addParsed(command, "--from", source.from, parseParameterizationKind,
            "Parameterization of a plain image (no brdfbake metadata): sphere | paraboloid | cube | latlong");
  command
      ->add_option("--mip-level", source.mipLevel,
                   "Read mip level L (0 = the map itself) of a map, cube faces or stack: from a tiled MIP-mapped "
                   "file, else from STEM_mipL.EXT")
      ->check(CLI::Range(0, 30));
  if (!cosView) return;
  command
      ->add_option("--cos-view", source.cosView,
                   "n.v in [0, 1], the cosine between the surface normal and the direction towards the viewer: where "
                   "an elevation stack is interpolated, and where a Fresnel table is read")
      ->check(CLI::Range(0.0, 1.0));
}

void addEnvironmentOptions(CLI::App* command, fs::path& environment, std::optional<ParameterizationKind>& from) {
  command->add_option("environment", environment, "Environment image (EXR, HDR, ...)")->required();
  addParsed(command, "--from", from, parseParameterizationKind,
            "Parameterization of a plain environment image (default: metadata, shape)");
}

void addToOption(CLI::App* command, ParameterizationKind& to) {
  addParsed(command, "--to", to, parseParameterizationKind,
            "Output parameterization: sphere | paraboloid | cube | latlong")
      ->required();
}

void addMapResolutionOption(CLI::App* command, int& resolution) {
  command->add_option("--resolution", resolution, "Texels per side (sphere), hemisphere, face, or rows (latlong)")
      ->default_val(256)
      ->check(CLI::Range(1, 65536));
}

void addMaxErrorOption(CLI::App* command, double& maxError, const std::string& bound) {
  command->add_option("--max-error", maxError, bound)->default_val(0.01)->check(CLI::Range(1e-6, 0.5));
}

void addSamplesPerTexelOption(CLI::App* command, int& samples, const std::string& help, bool oldSpelling) {
  command->add_option("--samples-per-texel", samples, help)->default_val(16)->check(CLI::Range(1, 4096));
  if (oldSpelling) command->add_option("--samples", samples, "(old spelling of --samples-per-texel)")->group("");
}

void addTexelFormatOption(CLI::App* command, std::optional<TexelFormat>& texelFormat) {
  addParsed(command, "--texel-format", texelFormat, parseTexelFormat,
            ".ktx2 .ktx .dds texels: rgba16f (default) | rgba32f | rgb16f | rgb32f | rgb9e5 | rg11b10f");
}

void addMapOutputOptions(CLI::App* command, MapOutputs& outputs) {
  command
      ->add_option("-o,--output", outputs.files,
                   std::string("Output map (") + kOutputContainers +
                       "); repeat -o to write the one map in several formats, computed once")
      ->required()
      ->allow_extra_args(false)  // one file per -o, so `-o OUT ENV` leaves ENV to the positional
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  addTexelFormatOption(command, outputs.texelFormat);
  command->add_flag_callback(
      "--faces", [&outputs] { outputs.layout = CubeLayout::Faces; },
      "Write a cube map as six files STEM_posx.EXT ... instead of a cross");
}

std::string flagFor(const std::string& field, const FieldFlags& renamed) {
  for (const auto& [name, flag] : renamed)
    if (name == field) return flag;
  std::string flag = "--" + field;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

Error namedByFlag(const Error& error, const FieldFlags& renamed) {
  if (!error.field().empty()) return Error(error.kind(), flagFor(error.field(), renamed) + ": " + error.problem());
  const std::string message = error.what();
  for (const auto& [field, flag] : renamed) {
    if (message.rfind(field + ": ", 0) == 0) return Error(error.kind(), flag + message.substr(field.size()));
  }
  return error;
}

}  // namespace brdfbake::cli
