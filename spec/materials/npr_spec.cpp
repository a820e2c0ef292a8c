// Hand-designed maps: "colorgram", "gooch", "silhouette", "hatching".
#include <brdfbake/brdf/npr.hpp>

#include <sstream>

#include "registry_entries.hpp"

namespace brdfbake::materials {
namespace {

std::string describeColor(const Rgb& c) {
  std::ostringstream out;
  out << "[" << c[0] << ", " << c[1] << ", " << c[2] << "]";
  return out.str();
}

// Library validation errors are reported at `path`.
template <class Make>
auto atPath(const std::string& path, Make make) {
  try {
    return make();
  } catch (const Error& e) {
    if (e.kind() == Error::Kind::InvalidInput) throw;
    throw specError(path, e.what());
  }
}

}  // namespace

std::shared_ptr<const Material> parseColorgram(JsonObjectReader& m, const MaterialContext&) {
  const auto& stopsJson = m.array("stops", 1024);
  if (stopsJson.empty())
    throw specError(m.child("stops"), "must hold at least one {\"angle\": degrees, \"color\": [r, g, b]}");
  std::vector<ColorStop> stops;
  for (std::size_t i = 0; i < stopsJson.size(); ++i) {
    JsonObjectReader stop(stopsJson[i], m.child("stops") + "[" + std::to_string(i) + "]");
    ColorStop s;
    s.angle = stop.number("angle", 0.0, 90.0);
    s.color = stop.color("color");
    if (!stops.empty() && !(s.angle > stops.back().angle)) {
      std::ostringstream message;
      message << "must be greater than the previous stop's angle (" << stops.back().angle << "), got " << s.angle;
      throw specError(stop.child("angle"), message.str());
    }
    stop.finish();
    stops.push_back(s);
  }
  const double blur = m.number("blur", 0.0, 0.0, 90.0, false);
  const double twist = m.number("twist", 0.0, -90.0, 90.0, false);
  const ColorgramBlend blend = m.parsed("blend", parseColorgramBlend);
  // The centre must leave the surface unchanged so it shows through at normal view (Zimmons & Bastos 1999 section 6).
  if (const auto neutral = ColorgramMaterial::neutralColor(blend)) {
    const Rgb centre = stops.front().color;
    if (!((centre - *neutral).abs() < 1e-12).all()) {
      throw specError(m.child("stops") + "[0].color",
                      "the colour at the centre (angle 0) must be " + describeColor(*neutral) + " for blend \"" +
                          std::string(toString(blend)) + "\", so the surface shows through at normal view; got " +
                          describeColor(centre) +
                          " (use \"blend\": \"replace\" for a map that replaces the surface colour)");
    }
  }
  return atPath(m.path(), [&] {
    return std::make_shared<ColorgramMaterial>(ColorGradient(std::move(stops), blur), twist, blend);
  });
}

std::shared_ptr<const Material> parseGooch(JsonObjectReader& m, const MaterialContext&) {
  GoochParams p;
  p.cool = m.color("cool", p.cool);
  p.warm = m.color("warm", p.warm);
  p.highlight = m.color("highlight", p.highlight);
  p.highlightSize = m.number("highlight_size", p.highlightSize, 0.0, 180.0, false);
  p.blur = m.number("blur", p.blur, 0.0, 180.0, false);
  if (m.has("light_direction")) p.lightDirection = m.direction("light_direction");
  return atPath(m.path(), [&] { return std::make_shared<GoochMaterial>(p); });
}

std::shared_ptr<const Material> parseSilhouette(JsonObjectReader& m, const MaterialContext&) {
  const double width = m.number("width", 0.0, 90.0, /*exclusiveMinimum=*/true);
  const Rgb color = m.color("color", Rgb::Zero());
  const Rgb background = m.color("background", Rgb::Ones());
  return atPath(m.path(), [&] { return std::make_shared<SilhouetteMaterial>(width, color, background); });
}

std::shared_ptr<const Material> parseHatching(JsonObjectReader& m, const MaterialContext&) {
  HatchingParams p;
  p.width = m.number("width", p.width, 0.0, 90.0, true);
  p.spacing = m.number("spacing", p.spacing, 0.0, 2.0, true);
  p.angle = m.number("angle", p.angle, -360.0, 360.0, false);
  p.ink = m.color("ink", p.ink);
  p.paper = m.color("paper", p.paper);
  return atPath(m.path(), [&] { return std::make_shared<HatchingMaterial>(p); });
}

}  // namespace brdfbake::materials
