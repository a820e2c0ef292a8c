#pragma once
/// @file
/// Hand-designed maps: colorgrams (Zimmons & Bastos 1999 section 6) and the non-photorealistic maps of Heidrich 2000
/// section 4 (Gooch cool-to-warm shading, silhouette rings, hatching near silhouettes).
///
/// Every model here is a function of the surface normal the texel stands for,
/// n = normalize(r + v) (geometryForReflection), and so depends on the view; none uses lights.
/// Angles are in degrees. "theta" is the angle between the view vector and the normal (0 at the
/// centre of a sphere map, 90 at its rim). The map frame's "right" and "up" axes are those of
/// viewFrame(); for a sphere map (view +z, eye space) they are +x and +y, so the disc coordinates of
/// a texel are (n.right, n.up).

#include <brdfbake/brdf/material.hpp>

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace brdfbake {

/// Right and up axes perpendicular to a unit view vector: right = normalize(+y x view) (for view +z:
/// +x), up = view x right. If the view is within 1e-9 of +-y, right = +x.
struct ViewFrame {
  Vec3 right, up;
};
ViewFrame viewFrame(const Vec3& view);

/// The angle theta (degrees, in [0, 90]) between view and normal for the cosine N.V (clamped).
double viewAngleDegrees(double nDotV);

// ---- colorgrams ------------------------------------------------------------------------------

/// A colour stop of a radial gradient: the colour at angle theta = `angle` (degrees).
struct ColorStop {
  double angle = 0.0;
  Rgb color = Rgb::Ones();
};

/// How the renderer applies a colorgram map to the surface colour S (Zimmons & Bastos 1999 section 6):
/// replace: S' = map; modulate: S' = S * map (white leaves S unchanged); add: S' = S + map (black
/// leaves S unchanged). The map's texels are the same in each case; the mode is recorded in the
/// spec (and so in the map's metadata).
enum class ColorgramBlend { Replace, Modulate, Add };
/// "replace" | "modulate" | "add"; throws Error(InvalidArgument).
ColorgramBlend parseColorgramBlend(std::string_view name);
std::string_view toString(ColorgramBlend blend);

/// A radial colour gradient over theta in degrees, optionally blurred by a Gaussian in angle.
///
/// Unblurred, g(theta) interpolates the stops linearly and holds the first and last colours beyond
/// them. The blur convolves g with a Gaussian of standard deviation `blur` degrees, with g mirrored
/// about theta = 0 (a line through the map centre sees g(|theta|)) and held constant beyond the
/// last stop; it is evaluated exactly (piecewise-linear pieces against the Gaussian's erf and
/// density), so it never aliases.
class ColorGradient {
 public:
  /// Stops strictly increasing in angle, all in [0, 90], at least one; colours finite and >= 0;
  /// blur finite and >= 0. Throws Error(InvalidArgument).
  ColorGradient(std::vector<ColorStop> stops, double blurDegrees);
  /// The (blurred) gradient at theta degrees (any real value: mirrored below 0, held above 90).
  Rgb operator()(double thetaDegrees) const;
  /// The unblurred gradient.
  Rgb sharp(double thetaDegrees) const;
  const std::vector<ColorStop>& stops() const { return stops_; }
  double blur() const { return blur_; }

 private:
  struct Piece {
    double a, b;      // interval, may be infinite
    Rgb alpha, beta;  // g(t) = alpha + beta t on [a, b]
  };
  std::vector<ColorStop> stops_;
  double blur_;
  std::vector<Piece> pieces_;
};

/// A colorgram: rings of colour over theta, with a twist that shifts the rings with azimuth so
/// that left and right differ (Zimmons & Bastos 1999 section 6: the "twisted" map):
///   value = gradient(theta - twist * (n . right)),
/// n.right = sin(theta) cos(azimuth from right). The rings move inwards by up to `twist` degrees on
/// the right side of the map and outwards on the left; the shift is 0 at the centre and continuous.
/// For a modulating colorgram the centre should be white, so the surface shows through at normal
/// view (the spec layer enforces it: the colour at theta = 0 must be the blend's neutral colour).
class ColorgramMaterial final : public Material {
 public:
  /// twist finite, in [-90, 90]. Throws Error(InvalidArgument).
  ColorgramMaterial(ColorGradient gradient, double twistDegrees, ColorgramBlend blend);
  std::string_view model() const override { return "colorgram"; }
  Rgb unlit(const ShadingGeometry& g) const override;
  bool viewIndependent() const override { return false; }
  bool unlitSymmetricAboutView() const override { return twist_ == 0.0; }

  const ColorGradient& gradient() const { return gradient_; }
  double twist() const { return twist_; }
  ColorgramBlend blend() const { return blend_; }
  /// The colour the blend leaves the surface unchanged with: white (modulate), black (add);
  /// nullopt for replace.
  static std::optional<Rgb> neutralColor(ColorgramBlend blend);

 private:
  ColorGradient gradient_;
  double twist_;
  ColorgramBlend blend_;
};

/// Per-fleck texture-coordinate offsets for colorgram flecks (Zimmons & Bastos 1999 section 6.2): `count`
/// offsets (ds, dt), uniformly distributed in the disc of radius `radius` (texture-coordinate units:
/// the whole sphere map spans [0, 1]), from a fixed generator (SplitMix64 seeded with `seed`, so the
/// table is the same on every platform). The renderer gives fleck polygon i the offset i % count,
/// added to its generated sphere-map coordinates (e.g. glMatrixMode(GL_TEXTURE);
/// glTranslatef(ds, dt, 0) before drawing the fleck, or a per-fleck attribute in a shader), so each
/// fleck looks up a different ring of the colorgram and sparkles independently. radius in [0, 0.5].
/// Throws Error(InvalidArgument).
std::vector<Vec2> fleckOffsets(std::size_t count, double radius, std::uint64_t seed);

// ---- Heidrich 2000 section 4: non-photorealistic maps ------------------------------------------------

struct GoochParams {
  Rgb cool{0.10, 0.20, 0.75};  ///< the shadowed side
  Rgb warm{0.95, 0.80, 0.25};  ///< the side facing the light
  Rgb highlight = Rgb::Ones();
  double highlightSize = 10.0;         ///< angular radius (degrees) of the highlight disc about h; 0 = none
  double blur = 20.0;                  ///< Gaussian blur in angle (degrees) of both edges; 0 = hard edges
  Vec3 lightDirection{1.0, 1.0, 1.0};  ///< towards the light, map frame (normalised on construction)
};

/// Gooch cool-to-warm shading as a hand-drawn map (Heidrich 2000 section 4, after Gooch et al. 1999):
/// the cool colour on the half of the normal sphere facing away from the light, the warm colour on
/// the half facing it, and a highlight disc around the half vector h = normalize(l + v); the
/// edges blurred by a Gaussian of `blur` degrees:
///   t = Phi(psi / blur), psi = asin(n.l) (signed angle from the terminator, degrees);
///   w = Phi((highlightSize - angle(n, h)) / blur);
///   value = (1 - w) ((1 - t) cool + t warm) + w highlight,
/// Phi the standard normal CDF (a step for blur = 0).
class GoochMaterial final : public Material {
 public:
  /// Colours finite >= 0, sizes finite in [0, 180], light non-zero. Throws Error(InvalidArgument).
  explicit GoochMaterial(GoochParams params);
  std::string_view model() const override { return "gooch"; }
  Rgb unlit(const ShadingGeometry& g) const override;
  bool viewIndependent() const override { return false; }
  const GoochParams& params() const { return params_; }

 private:
  GoochParams params_;
};

/// A silhouette ring (Heidrich 2000 section 4, after Gooch et al. 1999): `color` where theta >
/// 90 - width (i.e. N.V < sin(width)), `background` elsewhere. In a sphere map of N texels the ring
/// is (1 - cos(width)) N / 2 texels wide (disc radius rho = sin(theta)).
class SilhouetteMaterial final : public Material {
 public:
  /// width finite in (0, 90]; colours finite >= 0. Throws Error(InvalidArgument).
  SilhouetteMaterial(double widthDegrees, const Rgb& color = Rgb::Zero(), const Rgb& background = Rgb::Ones());
  std::string_view model() const override { return "silhouette"; }
  Rgb unlit(const ShadingGeometry& g) const override;
  bool viewIndependent() const override { return false; }
  bool unlitSymmetricAboutView() const override { return true; }

  double width() const { return width_; }
  const Rgb& color() const { return color_; }
  const Rgb& background() const { return background_; }
  /// The ring width in texels of a sphere map of `resolution` texels: (1 - cos(width)) resolution / 2.
  double ringTexels(int resolution) const;
  /// The material for a mip level of `levelResolution` texels of a sphere map whose level 0 has
  /// `baseResolution` texels: the same ring width in texels as level 0 (Heidrich 2000 section 4's
  /// hand-made mip hierarchy), i.e. width_L = acos(max(0, 1 - (1 - cos(width)) base / level)),
  /// capped at 90 degrees (the whole disc) once the ring would be wider than the radius.
  SilhouetteMaterial forMipLevel(int baseResolution, int levelResolution) const;

 private:
  double width_;
  Rgb color_, background_;
  double sinWidth_;
};

struct HatchingParams {
  double width = 35.0;    ///< the hatched band: theta in [90 - width, 90], degrees, in (0, 90]
  double spacing = 0.05;  ///< distance between strokes, in map-disc units (sin theta; radius 1); > 0
  double angle = 45.0;    ///< stroke direction in the disc, degrees from the right axis towards up
  Rgb ink = Rgb::Zero();
  Rgb paper = Rgb::Ones();
};

/// Hatching near silhouettes (Heidrich 2000 section 4): paper in the middle of the map; inside the band
/// near the rim, parallel strokes whose thickness grows from 0 at the band's inner edge to the whole
/// stroke period at the rim, with cross strokes (perpendicular) in the outer half of the band.
/// With q = clamp((theta - (90 - width)) / width, 0, 1), disc coordinates (x, y) = (n.right, n.up)
/// and f(u) = u - floor(u):
///   stroke 1 where |f((x cos a + y sin a) / spacing) - 1/2| < q / 2,
///   stroke 2 where |f((-x sin a + y cos a) / spacing) - 1/2| < (2 q - 1) / 2.
class HatchingMaterial final : public Material {
 public:
  /// Throws Error(InvalidArgument) for out-of-range parameters.
  explicit HatchingMaterial(HatchingParams params);
  std::string_view model() const override { return "hatching"; }
  Rgb unlit(const ShadingGeometry& g) const override;
  bool viewIndependent() const override { return false; }
  const HatchingParams& params() const { return params_; }
  /// Fraction q of the stroke period inked at angle theta (degrees).
  double coverage(double thetaDegrees) const;

 private:
  HatchingParams params_;
};

}  // namespace brdfbake
