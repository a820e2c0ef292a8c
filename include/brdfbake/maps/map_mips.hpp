#pragma once
/// @file
/// Mip chains of environment maps weighted by solid angle (Heidrich 2000 section 2.4), seam-free:
/// paraboloid halves keep their border (each half fills its square with the other hemisphere, so
/// averaging carries it down every level; alignParaboloidBorder handles where the circle meets the
/// square's edge)
/// and cube faces get edge fixup at every level.
///
/// Storage (docs/prefilter.md): level 0 is the map itself at PATH; level k >= 1 is a full map of
/// resolution max(1, N >> k) at STEM_mipK.EXT (mipLevelPath, io/map_file.hpp), with its own metadata.

#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/parameterization.hpp>

#include <vector>

namespace brdfbake {

/// Resolution of mip level `level` (>= 0) of a map of `resolution` texels: max(1, resolution >> level).
int mipResolution(int resolution, int level);
/// Levels from `resolution` down to 1 texel: floor(log2(resolution)) + 1.
int mipLevelCount(int resolution);

/// The weight (sr) a texel gets when averaged into the next level: its exact solid angle
/// (texelSolidAngle), except for paraboloid maps, whose texels stand for their whole square
/// under the stereographic density 4 / (1 + x^2 + y^2)^2 continued outside the circle (the border
/// that replicates the other hemisphere). Sphere-map texels outside the disc weigh 0.
double mipTexelWeight(const Parameterization& map, int x, int y);

/// Level k+1 from level k (of `map`): each coarse texel is the weighted mean (mipTexelWeight) of
/// the fine texels whose centres fall inside it, region by region (2 x 2 for even sizes); texels
/// of zero total weight take the plain mean. Alpha is the coarse map's coverage.
Image downsampleEnvironment(const Image& fine, const Parameterization& fineMap);

/// Makes a cube cross seamless under per-face bilinear (clamp-to-face) lookups: each edge texel
/// and the texel facing it across the edge become their solid-angle-weighted mean, and the three
/// texels at each corner their mean. Faces of 1 texel become the mean of all six.
void fixCubeEdges(Image& image, const CubeMap& map);

/// Paraboloid halves fill their squares, but the unit circle touches each square's edges at four
/// points, where clamp-to-edge lookups see no border: between the outermost texel centres and the
/// edge, a lookup returns the ring texel of its own half, and at the equator the two halves would
/// disagree to first order. At equator points the two halves' local coordinates coincide, so this
/// sets every ring texel whose outer half (between its centre and the edge) the circle crosses, in
/// both halves, to the mean of the two: the front and back values lie at mirror-image directions
/// about the equator, so their mean is the value on the equator to second order, and lookups from
/// either side meet it. Applied to every level of 4 or more texels per hemisphere; the levels of 2
/// and 1 texels hold a hemisphere's mean per texel and cannot be seamless.
void alignParaboloidBorder(Image& image, const ParaboloidMap& map);

/// Levels 0 .. mipLevelCount(resolution) - 1; level 0 is `level0`, edge-fixed for cubes and
/// border-aligned for paraboloids, as every level.
std::vector<Image> environmentMipChain(const Image& level0, const Parameterization& map);

}  // namespace brdfbake
