#pragma once
/// @file
/// The parts of a BRDF times the cosine, f_r(l, v) max(0, n.l), seen as functions of the incident
/// direction l for one geometry (normal n, view v): where each part peaks, how wide it is, and a
/// probability density close to its shape to draw directions l from. Integrators over incident
/// directions (a material under an environment, env/material_under_environment.hpp) use it to place
/// samples (importance sampling, Pharr et al. "Physically Based Rendering" chapter 13) and to refine
/// sums where the integrand changes fast; the value itself always comes from Material::shade.
///
/// Unit vectors point away from the surface (docs/conventions.md). Densities are per steradian of l.

#include <brdfbake/core/math.hpp>

#include <optional>

namespace brdfbake {

enum class ReflectionLobeShape {
  /// max(0, axis.l) / pi about the axis (the normal): Lambertian parts. Sampled exactly.
  Cosine,
  /// (N + 1) / (2 pi) max(0, axis.l)^N about the axis: Phong lobes (axis the mirrored view) and
  /// Lafortune lobes (their own axis). Sampled exactly.
  PowerCosine,
  /// The half vector h = normalize(l + v) distributed as beckmannD(axis.h, m) (axis.h) about the
  /// axis (the normal), l = v mirrored about h: Cook-Torrance with Beckmann's distribution.
  Beckmann,
  /// The same with ggxD(axis.h, alpha): Cook-Torrance with GGX.
  Ggx,
  /// The same with Blinn's (N + 2) / (2 pi) (axis.h)^N: Blinn-Phong and fitted half-vector lobes.
  BlinnPhong,
};

/// One part of a BRDF times the cosine, for one geometry.
struct ReflectionLobe {
  ReflectionLobeShape shape = ReflectionLobeShape::Cosine;
  /// Unit: the normal (cosine and half-vector shapes) or the lobe's axis in l (power cosine).
  Vec3 axis = Vec3::UnitZ();
  /// N (power cosine, Blinn-Phong; >= 0), m (Beckmann) or alpha (GGX) (> 0); unused for cosine.
  double parameter = 0.0;
  /// The part's share of the reflected light (> 0; only ratios matter): how many of an integrator's
  /// samples it gets.
  double weight = 1.0;
};

/// A direction l drawn from the lobe's density for the view `view` (unit) from two numbers in [0, 1)
/// (inverse transform: the same numbers give the same direction). Half-vector shapes draw h and
/// mirror v about it; a half vector facing away from the view (v.h <= 0) gives nullopt (the density
/// below then integrates to less than 1 by that draw's probability).
std::optional<Vec3> sampleReflectionLobe(const ReflectionLobe& lobe, const Vec3& view, double u1, double u2);

/// The density (1/sr) with which sampleReflectionLobe draws the unit direction `light`:
/// cosine max(0, a.l) / pi, power cosine (N + 1) / (2 pi) max(0, a.l)^N, half-vector shapes
/// p(h) / (4 v.h) with p(h) = D(a.h) (a.h), h = normalize(l + v), 0 where v.h <= 0 or a.h <= 0.
double reflectionLobeDensity(const ReflectionLobe& lobe, const Vec3& view, const Vec3& light);

/// Where the lobe peaks in l: its axis (cosine, power cosine), or the view mirrored about the
/// normal (half-vector shapes).
Vec3 reflectionLobePeak(const ReflectionLobe& lobe, const Vec3& view);

/// The lobe's angular width in l (radians): the standard deviation of a Gaussian with the same
/// half-maximum angle (1/sqrt(N) for max(0, cos)^N), at most 1 (the cosine lobe's). Half-vector
/// shapes are twice as wide in l as in h (a half vector tilted by t tilts the mirrored view by 2t
/// in the plane of incidence): Beckmann sqrt(2) m, GGX 2 atan(0.644 alpha) / 1.177, Blinn-Phong
/// 2 / sqrt(N).
double reflectionLobeWidth(const ReflectionLobe& lobe);

}  // namespace brdfbake
