#include <brdfbake/bake/baked_mips.hpp>
#include <brdfbake/core/error.hpp>

namespace brdfbake {

std::vector<Image> bakeMipChain(ParameterizationKind kind, int resolution, const MipLevelFunction& levelFunction,
                                const BakeOptions& options, const Context& context) {
  const int levels = mipLevelCount(resolution);
  std::vector<Image> chain;
  chain.reserve(static_cast<std::size_t>(levels));
  for (int level = 0; level < levels; ++level) {
    const int levelResolution = mipResolution(resolution, level);
    const auto map = makeParameterization(kind, levelResolution);
    const auto function = levelFunction(level, levelResolution);
    require(function != nullptr, "mip level function returned null");
    chain.push_back(bake(*map, *function, options, context.part(double(level) / levels, double(level + 1) / levels)));
  }
  return chain;
}

std::vector<Image> silhouetteMipChain(const SilhouetteMaterial& material, int resolution, const BakeOptions& options,
                                      const Context& context) {
  return bakeMipChain(
      ParameterizationKind::Sphere, resolution,
      [&](int, int levelResolution) -> std::shared_ptr<const MapFunction> {
        auto level = std::make_shared<SilhouetteMaterial>(material.forMipLevel(resolution, levelResolution));
        return std::make_shared<MaterialMapFunction>(level, std::vector<DirectionalLight>{}, Vec3::UnitZ());
      },
      options, context);
}

}  // namespace brdfbake
