#include <brdfbake/bake/radial_profile.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

namespace brdfbake {

RadialProfile::RadialProfile(const Vec3& axis, std::vector<Rgb> texels) : texels_(std::move(texels)) {
  // Scaled to its largest component first: the norm of [1e308, 1e308, 0] overflows.
  const double scale = axis.cwiseAbs().maxCoeff();
  require(std::isfinite(scale) && scale > 0.0, "profile axis must be a finite non-zero vector");
  require(!texels_.empty(), "a profile needs at least one texel");
  for (const Rgb& t : texels_) require(t.allFinite(), "profile texels must be finite");
  axis_ = (axis / scale).normalized();
  const Vec3 helper = std::abs(axis_.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  tangent_ = axis_.cross(helper).normalized();
  bitangent_ = axis_.cross(tangent_);
}

double RadialProfile::coordinateFor(const Vec3& direction) const {
  return std::clamp((direction.normalized() - axis_).norm() / 2.0, 0.0, 1.0);
}

Vec3 RadialProfile::directionFor(double u, double phi) const {
  // cos(alpha) = 1 - 2 u^2, sin(alpha) = 2 u sqrt(1 - u^2).
  u = std::clamp(u, 0.0, 1.0);
  const double cosAlpha = 1.0 - 2.0 * u * u, sinAlpha = 2.0 * u * std::sqrt(std::max(0.0, 1.0 - u * u));
  return (cosAlpha * axis_ + sinAlpha * (std::cos(phi) * tangent_ + std::sin(phi) * bitangent_)).normalized();
}

Rgb RadialProfile::lookup(const Vec3& direction) const { return sampleLinear1d(texels_, coordinateFor(direction)); }

nlohmann::json RadialProfile::toJson() const {
  return {{"parameterization", "profile"},
          {"resolution", resolution()},
          {"axis", {axis_.x(), axis_.y(), axis_.z()}},
          {"coordinate",
           "u = |d - axis| / 2 = sin(angle to axis / 2); texel i at u = (i + 0.5) / N; for a sphere map "
           "about the view, u is the map radius |(2s - 1, 2t - 1)|"}};
}

Image RadialProfile::toImage() const {
  Image image(resolution(), 1);
  for (int i = 0; i < resolution(); ++i) {
    const Rgb& t = texels_[static_cast<std::size_t>(i)];
    image.set(i, 0, Rgba(t[0], t[1], t[2], 1.0));
  }
  image.metadata = toJson();
  return image;
}

namespace {

// A profile with a placeholder texel: the frame (coordinateFor, directionFor) about `axis`.
RadialProfile profileFrame(const Vec3& axis) { return RadialProfile(axis, std::vector<Rgb>(1, Rgb::Zero())); }

// Texel i of N: the mean over samplesPerTexel directions equal in solid angle (u^2 stratified
// uniformly over the ring [i/N, (i+1)/N]), each at its own azimuth (golden-angle sequence).
Rgb profileTexel(const MapFunction& function, const RadialProfile& frame, int i, int resolution, int samplesPerTexel) {
  const double goldenAngle = kPi * (3.0 - std::sqrt(5.0));
  const double a = static_cast<double>(i) / resolution, b = static_cast<double>(i + 1) / resolution;
  Rgb sum = Rgb::Zero();
  for (int k = 0; k < samplesPerTexel; ++k) {
    const double u2 = a * a + (b * b - a * a) * (k + 0.5) / samplesPerTexel;
    const double phi = goldenAngle * (static_cast<double>(i) * samplesPerTexel + k);
    sum += function.evaluate(frame.directionFor(std::sqrt(u2), phi));
  }
  return sum / samplesPerTexel;
}

// About the view, a profile is looked up through sphere-map coordinates: skip the rim band the
// sphere-map measure skips, for a sphere map of the same radial texel size (2N across).
bool aboutView(const Vec3& axis) { return (axis.normalized() - Vec3::UnitZ()).norm() < 1e-12; }
double profileRimCos(const Vec3& axis, int resolution) {
  return aboutView(axis) ? mapRimCos(ParameterizationKind::Sphere, 2 * resolution) : 2.0;
}

}  // namespace

RadialProfile bakeRadialProfile(const MapFunction& function, const Vec3& axis, int resolution, int samplesPerTexel,
                                const Context& context) {
  require(resolution >= 1, "profile resolution must be >= 1");
  require(samplesPerTexel >= 1, "samples per texel must be >= 1");
  const RadialProfile frame = profileFrame(axis);
  std::vector<Rgb> texels(static_cast<std::size_t>(resolution), Rgb::Zero());
  tbb::task_arena arena(context.arenaThreads());
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, resolution), [&](const tbb::blocked_range<int>& range) {
      context.checkCancelled();
      for (int i = range.begin(); i < range.end(); ++i)
        texels[static_cast<std::size_t>(i)] = profileTexel(function, frame, i, resolution, samplesPerTexel);
    });
  });
  context.report(1.0);
  return RadialProfile(axis, std::move(texels));
}

ErrorStats measureProfileError(const RadialProfile& profile, const ErrorProbes& probes, bool visibleSphere) {
  return probes.measure([&](const Vec3& r) { return profile.lookup(r); },
                        profileRimCos(profile.axis(), profile.resolution()),
                        aboutView(profile.axis()) && visibleSphere);
}

ErrorStats estimateProfileError(const MapFunction& function, const Vec3& axis, int resolution, int samplesPerTexel,
                                const ErrorProbes& probes, bool visibleSphere, const Context& context) {
  require(resolution >= 1, "profile resolution must be >= 1");
  require(samplesPerTexel >= 1, "samples per texel must be >= 1");
  const RadialProfile frame = profileFrame(axis);
  auto taps = [&](const Vec3& r, TexelTaps& out) {
    const LinearTaps t = linearTaps(resolution, frame.coordinateFor(r));
    out.count = 2;
    out.index[0] = t.i0, out.weight[0] = 1.0 - t.w;
    out.index[1] = t.i1, out.weight[1] = t.w;
  };
  auto texel = [&](long long i) {
    return profileTexel(function, frame, static_cast<int>(i), resolution, samplesPerTexel);
  };
  return measureSparseLookups(probes, resolution, taps, texel, profileRimCos(axis, resolution),
                              aboutView(axis) && visibleSphere, context);
}

ErrorStats measureProfileError(const RadialProfile& profile, const MapFunction& exact, const ErrorOptions& options) {
  return measureProfileError(profile, ErrorProbes(exact, options), options.visibleSphere);
}

}  // namespace brdfbake
