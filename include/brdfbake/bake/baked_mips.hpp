#pragma once
/// @file
/// Hand-made mip chains: each level baked from its own function instead of averaged from the level
/// above (Heidrich 2000 section 4: a silhouette ring that keeps its width in texels at every level).

#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <functional>
#include <memory>
#include <vector>

namespace brdfbake {

/// What a level is baked from: the function for `level`, whose map has `levelResolution` texels.
using MipLevelFunction = std::function<std::shared_ptr<const MapFunction>(int level, int levelResolution)>;

/// Bakes levels 0 .. mipLevelCount(resolution) - 1 of a map of the given kind, level L at
/// mipResolution(resolution, L), each with `options`. Returns them in order (index = level).
/// Throws what bake() throws, and Error(InvalidArgument) for resolution < 1.
std::vector<Image> bakeMipChain(ParameterizationKind kind, int resolution, const MipLevelFunction& levelFunction,
                                const BakeOptions& options = {}, const Context& context = {});

/// The silhouette mip chain of Heidrich 2000 section 4 for a sphere map (view +z): level L is the
/// silhouette ring of material.forMipLevel(resolution, mipResolution(resolution, L)), so the ring is
/// material.ringTexels(resolution) texels wide at every level (until it fills the disc), and a
/// renderer that picks the level whose texels match its pixels draws silhouettes of about constant
/// width whatever the curvature.
std::vector<Image> silhouetteMipChain(const SilhouetteMaterial& material, int resolution,
                                      const BakeOptions& options = {}, const Context& context = {});

}  // namespace brdfbake
