#include "disc_region.hpp"

#include <array>
#include <vector>

namespace brdfbake::detail {
namespace {

struct Chord {
  Vec2 a, b;            // entry and exit points, in counter-clockwise order
  bool startsAtCorner;  // a is the edge's start corner (t = 0)
  bool endsAtCorner;    // b is the edge's end corner (t = 1)
  int edge;             // which rectangle edge (0..3, counter-clockwise)
};

double chordIntegral(const Vec2& a, const Vec2& b, const RadialDensity& density) {
  const Vec2 dir = b - a;
  const double length = dir.norm();
  if (length == 0.0) return 0.0;
  const Vec2 unit = dir / length;
  const double d = a.x() * unit.y() - a.y() * unit.x();  // signed distance of the line from 0
  return density.chord(d, a.dot(unit), b.dot(unit));
}

// Counter-clockwise angle from a to b on the unit circle, in [0, 2 pi).
double ccwAngle(const Vec2& a, const Vec2& b) {
  double angle = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  return angle < 0.0 ? angle + kTwoPi : angle;
}

}  // namespace

double integrateOverDiscPart(double x0, double x1, double y0, double y1, const RadialDensity& density) {
  const std::array<Vec2, 4> corners{Vec2(x0, y0), Vec2(x1, y0), Vec2(x1, y1), Vec2(x0, y1)};
  std::vector<Chord> chords;
  for (int e = 0; e < 4; ++e) {
    const Vec2& p = corners[e];
    const Vec2 dir = corners[(e + 1) % 4] - p;
    const double a = dir.squaredNorm();
    if (a == 0.0) continue;
    // |p + t dir|^2 <= 1  <=>  a t^2 + b t + c <= 0
    const double b = 2.0 * p.dot(dir);
    const double c = p.squaredNorm() - 1.0;
    const double disc = b * b - 4.0 * a * c;
    if (disc <= 0.0) continue;
    const double sq = std::sqrt(disc);
    // Numerically stable roots.
    const double q = -0.5 * (b + std::copysign(sq, b));
    double t0 = q / a, t1 = (q != 0.0) ? c / q : -t0;
    if (t0 > t1) std::swap(t0, t1);
    const double lo = std::max(0.0, t0), hi = std::min(1.0, t1);
    if (!(hi > lo)) continue;
    const Vec2 entry = lo == 0.0 ? p : Vec2(p + lo * dir);
    const Vec2 exit = hi == 1.0 ? corners[(e + 1) % 4] : Vec2(p + hi * dir);
    chords.push_back({entry, exit, lo == 0.0, hi == 1.0, e});
  }
  if (chords.empty()) {
    const bool containsDisc = x0 <= -1.0 && x1 >= 1.0 && y0 <= -1.0 && y1 >= 1.0;
    return containsDisc ? density.arcWeight * kTwoPi : 0.0;
  }
  double total = 0.0;
  for (std::size_t i = 0; i < chords.size(); ++i) {
    const Chord& current = chords[i];
    const Chord& next = chords[(i + 1) % chords.size()];
    total += chordIntegral(current.a, current.b, density);
    // Consecutive edges meeting at a corner inside the disc continue the boundary directly;
    // otherwise it follows the circle from this chord's exit to the next chord's entry.
    const bool sharedCorner = current.endsAtCorner && next.startsAtCorner && next.edge == (current.edge + 1) % 4;
    if (!sharedCorner) {
      total += density.arcWeight * ccwAngle(current.b, next.a);
    }
  }
  return total;
}

}  // namespace brdfbake::detail
