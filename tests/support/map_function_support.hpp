#pragma once
// Helpers for tests of maps and lookups: a wrapper that forces the baker's general path, a sun alone
// as an environment, and reproducible random directions.
#include <brdfbake/bake/map_function.hpp>

#include <cmath>
#include <random>
#include <vector>

namespace brdfbake::test {

// Hides every decomposition (radial lobes, microfacet lobes, symmetry axis), forcing the general path.
class GeneralOnly final : public MapFunction {
 public:
  explicit GeneralOnly(const MapFunction& inner) : inner_(inner) {}
  Rgb evaluate(const Vec3& d) const override { return inner_.evaluate(d); }

 private:
  const MapFunction& inner_;
};

// Black, but for a uniform disc of radiance `radiance` and angular radius `radius` about `direction`.
class SunOnly final : public MapFunction {
 public:
  SunOnly(const Vec3& direction, double radius, double radiance)
      : direction_(direction.normalized()), cosRadius_(std::cos(radius)), radiance_(radiance) {}
  Rgb evaluate(const Vec3& d) const override {
    return d.normalized().dot(direction_) >= cosRadius_ ? Rgb::Constant(radiance_) : Rgb::Zero();
  }

 private:
  Vec3 direction_;
  double cosRadius_, radiance_;
};

// `count` unit directions uniform on the sphere (normalised Gaussian triples, std::mt19937(seed)).
inline std::vector<Vec3> randomDirections(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < count) out.push_back(Vec3(g(rng), g(rng), g(rng)).normalized());
  return out;
}

}  // namespace brdfbake::test
