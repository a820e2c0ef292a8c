// Colorgrams, fleck offsets and the NPR maps against their definitions and brute-force checks.
#include <gtest/gtest.h>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/core/error.hpp>

#include <random>

namespace brdfbake {
namespace {

// The geometry for a normal at angle theta (degrees) from the view +z, azimuth phi (degrees) from +x.
ShadingGeometry normalAt(double thetaDeg, double phiDeg) {
  const double t = radians(thetaDeg), p = radians(phiDeg);
  const Vec3 n(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
  const Vec3 v = Vec3::UnitZ();
  return {n, v, reflect(v, n)};
}

const std::vector<ColorStop> kRainbow{
    {0, Rgb(1, 1, 1)}, {30, Rgb(1, 1, 1)}, {50, Rgb(1, 0, 0)}, {65, Rgb(0, 1, 0)}, {80, Rgb(0, 0, 1)}};

TEST(ColorGradient, SharpInterpolatesStops) {
  const ColorGradient g(kRainbow, 0.0);
  EXPECT_LT((g(0) - Rgb(1, 1, 1)).abs().maxCoeff(), 1e-15);
  EXPECT_LT((g(40) - Rgb(1, 0.5, 0.5)).abs().maxCoeff(), 1e-15);
  EXPECT_LT((g(57.5) - Rgb(0.5, 0.5, 0)).abs().maxCoeff(), 1e-15);
  EXPECT_LT((g(89) - Rgb(0, 0, 1)).abs().maxCoeff(), 1e-15);  // held beyond the last stop
  EXPECT_LT((g(-40) - g(40)).abs().maxCoeff(), 1e-15);        // mirrored about the centre
  EXPECT_THROW(ColorGradient({}, 0.0), Error);
  EXPECT_THROW(ColorGradient({{10, Rgb::Ones()}, {10, Rgb::Zero()}}, 0.0), Error);
  EXPECT_THROW(ColorGradient({{95, Rgb::Ones()}}, 0.0), Error);
  EXPECT_THROW(ColorGradient(kRainbow, -1.0), Error);
}

TEST(ColorGradient, BlurIsGaussianConvolutionInAngle) {
  // Brute force: integrate sharp(t) N(t; theta, sigma) over +-10 sigma with a fine midpoint rule
  // (sharp() already mirrors below 0 and holds beyond 90).
  for (double sigma : {0.5, 2.0, 10.0}) {
    const ColorGradient blurred(kRainbow, sigma), sharp(kRainbow, 0.0);
    for (double theta = -5.0; theta <= 120.0; theta += 0.73) {
      Rgb sum = Rgb::Zero();
      const int steps = 20000;
      const double a = theta - 10 * sigma, dt = 20 * sigma / steps;
      for (int i = 0; i < steps; ++i) {
        const double t = a + (i + 0.5) * dt, u = (t - theta) / sigma;
        sum += sharp.sharp(t) * std::exp(-0.5 * u * u) / (sigma * std::sqrt(kTwoPi)) * dt;
      }
      EXPECT_LT((blurred(theta) - sum).abs().maxCoeff(), 1e-6) << sigma << " " << theta;
    }
  }
  // A constant gradient stays constant under any blur.
  const ColorGradient flat({{0, Rgb(0.2, 0.4, 0.6)}, {90, Rgb(0.2, 0.4, 0.6)}}, 30.0);
  for (double theta : {0.0, 45.0, 90.0}) EXPECT_LT((flat(theta) - Rgb(0.2, 0.4, 0.6)).abs().maxCoeff(), 1e-12);
}

TEST(Colorgram, RingsOverViewAngleWithTwist) {
  const ColorgramMaterial plain(ColorGradient(kRainbow, 0.0), 0.0, ColorgramBlend::Modulate);
  const ColorgramMaterial twisted(ColorGradient(kRainbow, 0.0), 15.0, ColorgramBlend::Modulate);
  for (double theta = 0; theta < 90; theta += 3.7) {
    for (double phi = 0; phi < 360; phi += 30) {
      const ShadingGeometry g = normalAt(theta, phi);
      EXPECT_LT((plain.unlit(g) - ColorGradient(kRainbow, 0.0)(theta)).abs().maxCoeff(), 1e-9) << theta;
      const double shift = 15.0 * std::sin(radians(theta)) * std::cos(radians(phi));
      EXPECT_LT((twisted.unlit(g) - ColorGradient(kRainbow, 0.0)(theta - shift)).abs().maxCoeff(), 1e-9)
          << theta << " " << phi;
    }
  }
  // Left and right differ (by the twist), top and bottom agree; the centre stays white.
  const ShadingGeometry right = normalAt(60, 0), left = normalAt(60, 180), up = normalAt(60, 90),
                        down = normalAt(60, 270);
  EXPECT_GT((twisted.unlit(right) - twisted.unlit(left)).abs().maxCoeff(), 0.3);
  EXPECT_LT((twisted.unlit(up) - twisted.unlit(down)).abs().maxCoeff(), 1e-9);
  EXPECT_LT((twisted.unlit(normalAt(0, 0)) - Rgb::Ones()).abs().maxCoeff(), 1e-12);
  EXPECT_EQ(ColorgramMaterial::neutralColor(ColorgramBlend::Modulate)->matrix(), Rgb::Ones().matrix());
  EXPECT_EQ(ColorgramMaterial::neutralColor(ColorgramBlend::Add)->matrix(), Rgb::Zero().matrix());
  EXPECT_FALSE(ColorgramMaterial::neutralColor(ColorgramBlend::Replace));
  EXPECT_EQ(parseColorgramBlend("add"), ColorgramBlend::Add);
  EXPECT_THROW(parseColorgramBlend("multiply"), Error);
  EXPECT_THROW(ColorgramMaterial(ColorGradient(kRainbow, 0.0), 120.0, ColorgramBlend::Add), Error);
}

TEST(Fleck, OffsetsAreSeededAndUniformInTheDisc) {
  const auto a = fleckOffsets(20000, 0.05, 42), b = fleckOffsets(20000, 0.05, 42), c = fleckOffsets(20000, 0.05, 43);
  ASSERT_EQ(a.size(), 20000u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  Vec2 mean = Vec2::Zero();
  int inner = 0;
  for (const auto& o : a) {
    EXPECT_LE(o.norm(), 0.05 + 1e-15);
    mean += o;
    if (o.norm() < 0.05 / std::sqrt(2.0)) ++inner;  // half the disc's area
  }
  mean /= a.size();
  // Uniform in a disc of radius R: each coordinate has standard deviation R / 2.
  EXPECT_LT(mean.norm(), 4 * 0.025 / std::sqrt(20000.0));
  EXPECT_NEAR(inner / 20000.0, 0.5, 0.015);
  for (const auto& o : fleckOffsets(10, 0.0, 1)) EXPECT_EQ(o.norm(), 0.0);
  EXPECT_THROW(fleckOffsets(1, 0.6, 1), Error);
}

// Heidrich 2000 section 4's Gooch map as brdf/npr.hpp writes it, typed out: t = Phi(psi / blur),
// psi = asin(n.l) in degrees; w = Phi((size - angle(n, h)) / blur), h = normalize(l + v);
// value = (1 - w) ((1 - t) cool + t warm) + w highlight; Phi a step for blur 0.
Rgb goochFormula(const GoochParams& p, const Vec3& n, const Vec3& v) {
  auto phi = [&](double x) {
    if (p.blur == 0.0) return x > 0 ? 1.0 : (x < 0 ? 0.0 : 0.5);
    return 0.5 * std::erfc(-x / p.blur / std::sqrt(2.0));
  };
  const Vec3 l = p.lightDirection.normalized(), h = (l + v).normalized();
  const double t = phi(std::asin(n.dot(l)) * 180.0 / kPi);
  const double w = p.highlightSize > 0 ? phi(p.highlightSize - std::acos(std::min(1.0, n.dot(h))) * 180.0 / kPi) : 0.0;
  return (1 - w) * ((1 - t) * p.cool + t * p.warm) + w * p.highlight;
}

TEST(Gooch, CoolToWarmWithHighlight) {
  GoochParams p;
  p.blur = 0.0;
  p.highlightSize = 10.0;
  p.lightDirection = Vec3(-1, 1, 0);  // terminator through the map centre
  const GoochMaterial hard(p);
  const Vec3 l = Vec3(-1, 1, 0).normalized(), v = Vec3::UnitZ();
  auto at = [&](const Vec3& n) { return ShadingGeometry{n.normalized(), v, reflect(v, Vec3(n.normalized()))}; };
  EXPECT_LT((hard.unlit(at(Vec3(1, -1, 0.5))) - p.cool).abs().maxCoeff(), 1e-15);  // facing away
  EXPECT_LT((hard.unlit(at(Vec3(-1, 1, 2.5))) - p.warm).abs().maxCoeff(), 1e-15);  // facing the light
  EXPECT_LT((hard.unlit(at(l + v)) - p.highlight).abs().maxCoeff(), 1e-15);        // at h
  // Blurred: on the terminator t = 1/2; at angle psi from it, t = Phi(psi / blur).
  p.blur = 20.0;
  p.highlightSize = 0.0;
  const GoochMaterial soft(p);
  EXPECT_LT((soft.unlit(at(Vec3(1, 1, 1))) - 0.5 * (p.cool + p.warm)).abs().maxCoeff(), 1e-12);
  const Vec3 n30 = std::cos(radians(60)) * l + std::sin(radians(60)) * v;  // psi = 30 degrees
  const double t = 0.5 * std::erfc(-(30.0 / 20.0) / std::sqrt(2.0));
  EXPECT_LT((soft.unlit(at(n30)) - ((1 - t) * p.cool + t * p.warm)).abs().maxCoeff(), 1e-12);
}

TEST(Gooch, EveryParameterActsAsTheFormulaSays) {
  // Each parameter changed from the defaults in turn, at 400 normals over the visible hemisphere,
  // against goochFormula (above); a hard map away from its two edges (0.01 degrees).
  std::vector<GoochParams> cases(7);
  cases[1].cool = Rgb(0.3, 0.0, 0.9);
  cases[2].warm = Rgb(1.0, 0.4, 0.0);
  cases[3].highlight = Rgb(0.5, 2.0, 0.25);
  cases[4].highlightSize = 35.0;
  cases[5].blur = 5.0;
  cases[6].lightDirection = Vec3(-2.0, 0.3, 0.4);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const GoochMaterial material(cases[c]);
    for (int i = 0; i < 400; ++i) {
      Vec3 n(u(rng), u(rng), 0.0);
      if (n.squaredNorm() >= 1.0) continue;
      n.z() = std::sqrt(1.0 - n.squaredNorm());
      const Vec3 v = Vec3::UnitZ();
      const Rgb expected = goochFormula(cases[c], n, v);
      EXPECT_LT((material.unlit({n, v, reflect(v, n)}) - expected).abs().maxCoeff(), 1e-12) << "case " << c;
    }
  }
  GoochParams hard;
  hard.blur = 0.0;
  const GoochMaterial hardMaterial(hard);
  const Vec3 l = hard.lightDirection.normalized(), h = (l + Vec3::UnitZ()).normalized();
  for (int i = 0; i < 400; ++i) {
    Vec3 n(u(rng), u(rng), 0.0);
    if (n.squaredNorm() >= 1.0) continue;
    n.z() = std::sqrt(1.0 - n.squaredNorm());
    const double psi = degrees(std::asin(n.dot(l))), angle = degrees(std::acos(std::min(1.0, n.dot(h))));
    if (std::abs(psi) < 0.01 || std::abs(angle - hard.highlightSize) < 0.01) continue;
    const Rgb expected = angle < hard.highlightSize ? hard.highlight : (psi > 0 ? hard.warm : hard.cool);
    EXPECT_EQ(hardMaterial.unlit({n, Vec3::UnitZ(), reflect(Vec3(Vec3::UnitZ()), n)}).matrix(), expected.matrix());
  }
}

TEST(Silhouette, RingNearTheRimAndMipWidths) {
  const SilhouetteMaterial s(12.0);
  for (double theta = 0; theta <= 90; theta += 0.25) {
    const Rgb expected = theta > 78.0 + 1e-9 ? Rgb::Zero() : Rgb::Ones();
    if (std::abs(theta - 78.0) < 1e-6) continue;
    EXPECT_EQ(s.unlit(normalAt(theta, 33)).matrix(), expected.matrix()) << theta;
  }
  EXPECT_NEAR(s.ringTexels(256), (1 - std::cos(radians(12))) * 128, 1e-12);
  // Every level keeps level 0's ring width in texels until the ring fills the disc.
  for (int level = 1; level <= 8; ++level) {
    const int res = 256 >> level;
    const SilhouetteMaterial m = s.forMipLevel(256, res);
    const double texels = std::min(m.ringTexels(res), res / 2.0);
    EXPECT_NEAR(texels, std::min(s.ringTexels(256), res / 2.0), 1e-9) << level;
    EXPECT_GE(m.width(), s.width());
  }
  EXPECT_EQ(s.forMipLevel(256, 1).width(), 90.0);
  EXPECT_THROW(SilhouetteMaterial(0.0), Error);
  EXPECT_THROW(SilhouetteMaterial(91.0), Error);
}

TEST(Hatching, StrokesOnlyNearTheSilhouette) {
  HatchingParams p;
  p.width = 40.0;
  p.spacing = 0.05;
  const HatchingMaterial h(p);
  for (double theta = 0; theta < 50; theta += 1) {
    for (double phi = 0; phi < 360; phi += 17) EXPECT_EQ(h.unlit(normalAt(theta, phi)).matrix(), p.paper.matrix());
  }
  EXPECT_NEAR(h.coverage(70.0), 0.5, 1e-12);
  EXPECT_EQ(h.coverage(95.0), 1.0);
  // The inked fraction at angle theta is f(q) = q (one stroke family) for q <= 1/2, and
  // q + (1 - q)(2q - 1) (two independent families) above. Brute force: points uniform in the map
  // disc (so the stroke phase is uniform), inked fraction against the mean of f(q) in each band.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double edges[] = {50.0, 60.0, 70.0, 80.0, 90.0};
  for (int band = 0; band < 4; ++band) {
    double ink = 0.0, expected = 0.0;
    int count = 0;
    while (count < 40000) {
      const double x = u(rng), y = u(rng), rho2 = x * x + y * y;
      if (rho2 >= 1.0) continue;
      const double theta = degrees(std::asin(std::sqrt(rho2)));
      if (theta < edges[band] || theta >= edges[band + 1]) continue;
      const Vec3 n(x, y, std::sqrt(1.0 - rho2));
      const double q = h.coverage(theta);
      expected += q <= 0.5 ? q : q + (1 - q) * (2 * q - 1);
      ink += h.unlit({n, Vec3::UnitZ(), reflect(Vec3(Vec3::UnitZ()), n)})[0] == 0.0;
      ++count;
    }
    EXPECT_NEAR(ink / count, expected / count, 0.01) << edges[band];
  }
}

TEST(Hatching, EveryParameterActsAsTheFormulaSays) {
  // brdf/npr.hpp's strokes typed out: q = clamp((theta - (90 - width)) / width, 0, 1), (x, y) the
  // normal's disc coordinates, stroke 1 where |frac((x cos a + y sin a) / spacing) - 1/2| < q / 2,
  // stroke 2 where |frac((-x sin a + y cos a) / spacing) - 1/2| < (2 q - 1) / 2; points within
  // 1e-9 of a stroke's edge are skipped. Each parameter changed from the defaults in turn.
  std::vector<HatchingParams> cases(6);
  cases[1].width = 70.0;
  cases[2].spacing = 0.13;
  cases[3].angle = -20.0;
  cases[4].ink = Rgb(0.2, 0.1, 0.5);
  cases[5].paper = Rgb(0.9, 0.85, 0.7);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const HatchingParams& p = cases[c];
    const HatchingMaterial material(p);
    int inked = 0, checked = 0;
    while (checked < 3000) {
      const double x = u(rng), y = u(rng), rho2 = x * x + y * y;
      if (rho2 >= 1.0) continue;
      const Vec3 n(x, y, std::sqrt(1.0 - rho2));
      const double theta = degrees(std::acos(n.z()));
      const double q = std::clamp((theta - (90.0 - p.width)) / p.width, 0.0, 1.0);
      const double a = radians(p.angle);
      const double u1 = (x * std::cos(a) + y * std::sin(a)) / p.spacing,
                   u2 = (-x * std::sin(a) + y * std::cos(a)) / p.spacing;
      const double d1 = std::abs(u1 - std::floor(u1) - 0.5) - q / 2,
                   d2 = std::abs(u2 - std::floor(u2) - 0.5) - (2 * q - 1) / 2;
      if (std::abs(d1) < 1e-9 || std::abs(d2) < 1e-9) continue;
      const bool ink = q > 0 && (d1 < 0 || d2 < 0);
      inked += ink;
      ++checked;
      EXPECT_EQ(material.unlit({n, Vec3::UnitZ(), reflect(Vec3(Vec3::UnitZ()), n)}).matrix(),
                (ink ? p.ink : p.paper).matrix())
          << "case " << c << " at (" << x << ", " << y << ")";
    }
    EXPECT_GT(inked, 100) << "case " << c;  // the comparison saw both colours
  }
}

TEST(Silhouette, ColoursAndWidthActAsTheFormulaSays) {
  // `color` where n.v < sin(width), `background` elsewhere; any view, not only +z.
  const Rgb ring(0.1, 0.6, 0.3), background(0.9, 0.2, 0.7);
  for (double width : {3.0, 20.0, 65.0}) {
    const SilhouetteMaterial s(width, ring, background);
    for (const Vec3& view : {Vec3(Vec3::UnitZ()), Vec3(Vec3(1, 2, 0.5).normalized())}) {
      const ViewFrame f = viewFrame(view);
      for (double theta = 0.0; theta < 90.0; theta += 0.37) {
        const double t = radians(theta);
        const Vec3 n = std::cos(t) * view + std::sin(t) * (0.6 * f.right + 0.8 * f.up);
        if (std::abs(n.dot(view) - std::sin(radians(width))) < 1e-9) continue;
        const Rgb expected = n.dot(view) < std::sin(radians(width)) ? ring : background;
        EXPECT_EQ(s.unlit({n, view, reflect(view, n)}).matrix(), expected.matrix()) << width << " " << theta;
      }
    }
  }
}

TEST(ViewFrame, SphereMapAxes) {
  const ViewFrame f = viewFrame(Vec3::UnitZ());
  EXPECT_LT((f.right - Vec3::UnitX()).norm(), 1e-15);
  EXPECT_LT((f.up - Vec3::UnitY()).norm(), 1e-15);
  const ViewFrame g = viewFrame(Vec3::UnitY());
  EXPECT_NEAR(g.right.dot(Vec3::UnitY()), 0.0, 1e-15);
  EXPECT_NEAR(g.up.norm(), 1.0, 1e-15);
}

}  // namespace
}  // namespace brdfbake
