#pragma once
// A map's outputs: "output" or "outputs" (several files from one computation) and "texel_format",
// parsed (map_outputs.cpp) for spec.cpp's parseMap. Private to brdfbake::spec.
#include <brdfbake/io/json_reader.hpp>
#include <brdfbake/spec/spec.hpp>

#include <filesystem>

namespace brdfbake::spec_detail {

// "output": FILE or "outputs": [FILE, ...] (one of the two), each a path of a format brdfbake writes,
// resolved against `baseDirectory`; fills MapSpec::output, moreOutputs and outputList. Neither leaves the
// map in memory (no outputs) when `inMemory`, and is refused otherwise.
void parseMapOutputs(JsonObjectReader& map, MapSpec& spec, const std::filesystem::path& baseDirectory, bool inMemory);
// A map made in memory asks for no file of its own (mips beside it, a Fresnel table, SH, an elevation stack).
void refuseFilesInMemory(const MapSpec& spec);

// "texel_format" (after the map's content is parsed, so the shape is known), then every output checked
// against what the map will hold (MapSpec::outputProblem), the error naming the output's JSON path.
void parseTexelFormatAndCheckOutputs(JsonObjectReader& map, MapSpec& spec);

}  // namespace brdfbake::spec_detail
