// `auto` (chooseConfiguration): the choice, its measured error, bakes, estimates and CPU time
// (all threads) for the cases of tests/bake/test_highlight_error.cpp and test_auto_config.cpp,
// every parameterization at 0.5 %, and copper with and without profiles (docs/accuracy.md).
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <ctime>
#include <iostream>
#include <memory>
namespace {
using namespace brdfbake;
struct C {
  std::string name;
  std::shared_ptr<const Material> m;
  std::vector<DirectionalLight> l;
};
void run(const std::string& set, const C& c, const AutoOptions& o) {
  const MaterialMapFunction f(c.m, c.l, Vec3::UnitZ());
  const std::clock_t t0 = std::clock();
  std::string chosen;
  double err = 0;
  int bakes = 0, est = 0;
  try {
    AutoResult r = chooseConfiguration(f, o);
    chosen = r.chosen.describe();
    err = r.error;
    bakes = r.bakes;
    est = r.estimated;
  } catch (const std::exception& e) {
    chosen = std::string("ERROR ") + e.what();
  }
  const double cpu = double(std::clock() - t0) / CLOCKS_PER_SEC;
  std::cout << set << " | " << c.name << " | " << chosen << " | " << err << " | bakes " << bakes << " est " << est
            << " | cpu " << cpu << " s\n";
}
}  // namespace

int main() {
  const std::vector<DirectionalLight> one{{Vec3(0.2, 0.5, 1.0).normalized(), Rgb::Ones()}};
  const std::vector<DirectionalLight> three{{Vec3(0.2, 0.5, 1.0).normalized(), Rgb::Ones()},
                                            {Vec3(-0.6, 0.1, 0.8).normalized(), Rgb(0.5, 0.6, 0.7)},
                                            {Vec3(0.3, -0.7, -0.4).normalized(), Rgb(0.2, 0.2, 0.9)}};
  CookTorranceParams ct;
  ct.mode = CookTorranceMode::Lighting;
  ct.roughness = 0.05;
  ct.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  std::vector<C> hl;
  for (double n : {10.0, 100.0, 1000.0, 10000.0})
    hl.push_back(
        {"phong " + std::to_string(int(n)) + ", one light", std::make_shared<PhongMaterial>(Rgb::Ones(), n), one});
  hl.push_back({"phong 1000, three lights", std::make_shared<PhongMaterial>(Rgb::Ones(), 1000.0), three});
  hl.push_back({"cook-torrance m=0.05, one light", std::make_shared<CookTorranceMaterial>(ct), one});
  hl.push_back({"cook-torrance m=0.05, three lights", std::make_shared<CookTorranceMaterial>(ct), three});
  AutoOptions h;
  h.parameterizations = {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid};
  h.samplesPerTexel = {1, 4};
  h.maxError = 0.02;
  for (auto& c : hl) run("highlight", c, h);
  CookTorranceParams copper;
  copper.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  copper.roughness = 0.4;
  std::vector<C> ac{
      {"phong eye", std::make_shared<PhongMaterial>(Rgb::Ones(), 30.0), {{Vec3::UnitZ(), Rgb::Ones()}}},
      {"phong general", std::make_shared<PhongMaterial>(Rgb::Ones(), 80.0), {{Vec3(1, 1, 1), Rgb::Ones()}}},
      {"blinn exact",
       std::make_shared<BlinnPhongMaterial>(Rgb::Ones(), 20.0, BlinnConversion::Exact),
       {{Vec3(0, 1, 2), Rgb::Ones()}}},
      {"cook-torrance reflectance", std::make_shared<CookTorranceMaterial>(copper), {}}};
  AutoOptions a;
  a.parameterizations = {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid};
  a.resolutions = {16, 32, 64, 128};
  a.samplesPerTexel = {1, 4};
  a.maxError = 0.01;
  a.error.samples = 4000;
  for (auto& c : ac) run("auto_config", c, a);
  // all four kinds, default resolutions and spt, 0.005
  AutoOptions all;
  all.parameterizations = {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                           ParameterizationKind::LatLong};
  all.maxError = 0.005;
  for (auto& c : hl) run("all kinds 0.005", c, all);
  // profile copper
  CookTorranceParams cr;
  cr.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  cr.roughness = 0.4;
  AutoOptions p;
  p.parameterizations = {ParameterizationKind::Sphere};
  p.resolutions = {16, 32, 64, 128, 256, 512, 1024};
  p.samplesPerTexel = {1, 4};
  p.maxError = 0.002;
  p.error.samples = 4000;
  C copperC{"copper reflectance", std::make_shared<CookTorranceMaterial>(cr), {}};
  run("profile off", copperC, p);
  p.allowRadialProfile = true;
  run("profile on", copperC, p);
  // The example of issue 11: Phong 200, two lights, view free (paraboloid, cube, lat-long), 0.5 %.
  AutoOptions free;
  free.parameterizations = {ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                            ParameterizationKind::LatLong};
  free.maxError = 0.005;
  C issue11{"phong 200, two lights",
            std::make_shared<PhongMaterial>(Rgb::Ones(), 200.0),
            {{Vec3(0.2, 0.5, 1.0).normalized(), Rgb::Ones()}, {Vec3(0, 0, -1), Rgb(0, 0, 0.001)}}};
  run("issue 11 example", issue11, free);
}
