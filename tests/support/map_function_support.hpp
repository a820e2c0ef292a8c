#pragma once
// Helpers for tests of maps and lookups: a wrapper that forces the baker's general path, and
// reproducible random directions.
#include <brdfbake/bake/map_function.hpp>

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

// `count` unit directions uniform on the sphere (normalised Gaussian triples, std::mt19937(seed)).
inline std::vector<Vec3> randomDirections(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < count) out.push_back(Vec3(g(rng), g(rng), g(rng)).normalized());
  return out;
}

}  // namespace brdfbake::test
