#include <brdfbake/run/prefilter_job.hpp>

#include "map_runners.hpp"

namespace brdfbake {

namespace {

nlohmann::json vectorJson(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json glossChainJson(const PrefilterRequest& request) {
  nlohmann::json chain = nlohmann::json::object();
  if (request.glossScale) chain["scale"] = *request.glossScale;
  if (request.glossBias) chain["bias"] = *request.glossBias;
  if (request.mipCount) chain["levels"] = *request.mipCount;
  if (!request.edgeFixup) chain["edge_fixup"] = false;
  return chain;
}

std::string lobeOf(const PrefilterRequest& request) {
  if (!request.chain) return request.lobe;
  if (!request.lobe.empty() && request.lobe != *request.chain) {
    throw Error(Error::Kind::InvalidArgument, "prefilter: maps[0].environment.lobe: a " + *request.chain +
                                                  " chain sets every level's lobe; leave the lobe out, got \"" +
                                                  request.lobe + "\"");
  }
  return *request.chain;
}

nlohmann::json environmentJson(const PrefilterRequest& request) {
  nlohmann::json e = {{"file", request.environment.string()}, {"lobe", lobeOf(request)}};
  if (request.method != "auto") e["method"] = request.method;
  if (request.maxError != 0.01) e["max_error"] = request.maxError;
  if (request.from) e["from"] = *request.from;
  if (request.mips) e["mips"] = true;
  if (request.tiled) e["mip_layout"] = "tiled";
  if (request.view) e["view"] = vectorJson(*request.view);
  if (request.up) e["up"] = vectorJson(*request.up);
  if (request.elevations) e["elevations"] = *request.elevations;
  if (request.fresnelIor) e["fresnel"] = {{"ior", *request.fresnelIor}};
  if (request.combine) e["combine"] = *request.combine;
  if (const nlohmann::json chain = glossChainJson(request); !chain.empty() || request.chain) e["gloss_chain"] = chain;
  if (request.shOutput) e["sh_output"] = request.shOutput->string();
  if (request.shFormat) e["sh_format"] = *request.shFormat;
  return e;
}

}  // namespace

nlohmann::json prefilterSpec(const PrefilterRequest& request) {
  nlohmann::json map = {
      {"parameterization", request.to}, {"resolution", request.resolution}, {"environment", environmentJson(request)}};
  if (request.samplesPerTexel != 16) map["samples_per_texel"] = request.samplesPerTexel;
  if (request.faces) map["layout"] = "faces";
  run_detail::putOutputs(map, request.output, request.moreOutputs, request.texelFormat);
  return {{"maps", nlohmann::json::array({map})}};
}

MapResult prefilterEnvironment(const PrefilterRequest& request, const JobOptions& options) {
  return runOneMapSpec(prefilterSpec(request), "prefilter", options);
}

}  // namespace brdfbake
