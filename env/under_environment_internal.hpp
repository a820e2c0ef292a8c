#pragma once
// Internals of material_under_environment.cpp: the environment split into bright texels and the
// rest, the integrals of a material over them (filtered importance sampling of the BRDF's reflection
// lobes, and the reference sum over a quadtree of the rest's mip chain), and the polar grid of
// normals the map is interpolated from. Directions are in eye space unless named env.
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/env/environment.hpp>

#include <memory>
#include <vector>

#include "prefilter_internal.hpp"

namespace brdfbake::detail {

// One bright texel of the input: its centre and corners' directions (environment frame), the radiance
// above the threshold times its solid angle (an irradiance at normal incidence), and its angular size.
struct BrightTexel {
  Vec3 direction;
  Rgb power;
  double angle = 0.0;
  int x = 0, y = 0;  // in the input image
};

// The environment as bright texels (explicit lights) plus the rest, clipped at the threshold: a texel
// of luminance Y above it keeps L t / Y in the rest and gives L (1 - t / Y) to the lights (its colour
// kept). The threshold is `factor` x the environment's solid-angle mean luminance, raised so that at
// most `maxTexels` texels exceed it; none when no texel does.
struct EnvironmentSplit {
  std::vector<BrightTexel> texels;
  Environment rest;
  double threshold = 0.0;
  double brightShare = 0.0;  // the lights' share of ∫ Y dω over the sphere
};
EnvironmentSplit splitEnvironment(const Environment& environment, double factor, int maxTexels);

// The bright texels as lights in eye space, each split into sub x sub sub-lights over its footprint
// (through the input's inverse mapping), so lobes narrower than a texel see its extent.
class LightSet {
 public:
  LightSet(const Environment& input, const std::vector<BrightTexel>& texels, const Mat3& environmentToEye, int sub);
  // Σ shade(g, l_i) power_i.
  Rgb sum(const Material& material, const ShadingGeometry& g) const;
  std::size_t size() const { return directions_.size(); }

 private:
  std::vector<Vec3> directions_;
  std::vector<Rgb> powers_;
};

// Sub-samples per side a texel of angular size `angle` needs under a lobe of width `width`: enough
// that they are no farther apart than width / perWidth (1 to `limit`).
int subdivisionFor(double angle, double width, double perWidth, int limit);

// ∫ shade(g, l) L(l) dω over the rest by filtered importance sampling (Křivánek & Colbert 2008):
// about `samples` directions drawn from the lobes' mixture (each lobe its share by weight, at
// least samples / (4 lobes)), each reading the rest's mip chain trilinearly at the level of its own
// solid angle 1 / (Σ_c K_c p_c(l)), weighted by the multi-sample balance heuristic f / Σ_c K_c p_c.
class LobeSampler {
 public:
  LobeSampler(const LatLongPyramid& rest, const Mat3& eyeToEnvironment, int samples);
  Rgb integrate(const Material& material, const ShadingGeometry& g, const std::vector<ReflectionLobe>& lobes) const;
  int samples() const { return samples_; }

 private:
  const LatLongPyramid& rest_;
  Mat3 eyeToEnvironment_;
  int samples_;
  double equatorTexel_;  // solid angle of a level-0 texel at the equator
};

// The reference: Σ shade(g, l) L(l) Ω over the environment's texels. The bright texels one by one,
// split into sub-samples no wider than an eighth of the narrowest lobe; the rest over a quadtree of
// its mip chain from 16 rows down, a texel refined while it is wider than a quarter of the local
// scale of the integrand: for each lobe max(width, d / 3) at angle d beyond the texel from its
// peak (a Gaussian's relative slope, a GGX tail's), 1 for the cosine, and the texel's own size where
// it straddles the horizon of n (down to a degree); level-0 texels still too wide are split into
// exact solid-angle sub-samples (up to 16 x 16).
class ReferenceSum {
 public:
  ReferenceSum(const Environment& input, const EnvironmentSplit& split, const LatLongPyramid& rest,
               const Mat3& eyeToEnvironment);
  Rgb value(const Material& material, const ShadingGeometry& g) const;

 private:
  void visit(const Material& material, const ShadingGeometry& g, const std::vector<ReflectionLobe>& lobes,
             const std::vector<Vec3>& peaks, int level, int x, int y, Rgb& sum) const;
  void sumLevelZero(const Material& material, const ShadingGeometry& g, int x, int y, int sub, Rgb& sum) const;
  const Environment& input_;
  const EnvironmentSplit& split_;
  const LatLongPyramid& rest_;
  Mat3 eyeToEnvironment_, environmentToEye_;
  int startLevel_ = 0;
};

// A function of the normal on a polar grid about the view: rows at theta_i = i pi / (2 R), i = 0 ... R
// (the last on the rim, n.v = 0), columns at phi_j = 2 pi j / C (C even) in the frame (t, b, v),
// interpolated bicubically (Catmull-Rom; wrapped in phi, continued across the pole, extended
// linearly beyond the rim). Set every node, then finish() before value().
class NormalGrid {
 public:
  NormalGrid(const Vec3& view, int rows, int columns);
  int rows() const { return rows_; }  // R + 1 rows
  int columns() const { return columns_; }
  Vec3 normal(int row, int column) const;
  void set(int row, int column, const Rgb& value) { values_[index(row, column)] = value; }
  Rgb at(int row, int column) const { return values_[index(row, column)]; }
  // Builds the padded table value() reads: a row across the pole, two beyond the rim, columns wrapped.
  void finish();
  Rgb value(const Vec3& normal) const;
  // Polar angle and azimuth (in [0, 2 pi)) of a unit normal in the grid's frame.
  void angles(const Vec3& normal, double& theta, double& phi) const;
  double rowSpacing() const { return dTheta_; }
  double columnSpacing() const { return dPhi_; }

 private:
  std::size_t index(int row, int column) const { return static_cast<std::size_t>(row) * columns_ + column; }
  Vec3 t_, b_, v_;
  int rows_, columns_;
  double dTheta_, dPhi_;
  std::vector<Rgb> values_;
  // Rows -1 ... R + 2 and columns -1 ... C + 1, row-major.
  std::vector<Rgb> padded_;
  int paddedColumns_ = 0;
};

}  // namespace brdfbake::detail
