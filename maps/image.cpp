#include <brdfbake/core/error.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/maps/image.hpp>

#include <algorithm>
#include <cmath>

namespace brdfbake {

Image::Image(int width, int height, const Rgba& fill) : width_(width), height_(height) {
  require(width >= 1 && height >= 1, "image size must be at least 1 x 1");
  requireWithinMemoryBudget(4.0 * sizeof(float) * width * height,
                            "a " + std::to_string(width) + " x " + std::to_string(height) + " float RGBA image");
  pixels_.resize(static_cast<std::size_t>(width) * height * 4);
  for (std::size_t i = 0; i < pixels_.size(); i += 4) {
    for (int c = 0; c < 4; ++c) pixels_[i + c] = static_cast<float>(fill[c]);
  }
}

nlohmann::json MapInfo::toJson() const {
  return {{"parameterization", std::string(toString(parameterization))},
          {"resolution", resolution},
          {"convention_version", conventionVersion},
          {"brdfbake_version", BRDFBAKE_VERSION_STRING},
          {"spec", spec}};
}

MapInfo MapInfo::fromJson(const nlohmann::json& metadata) {
  auto missing = [](const char* key) {
    return Error(Error::Kind::InvalidInput, std::string("map metadata has no valid '") + key + "'");
  };
  if (!metadata.is_object()) throw missing("parameterization");
  MapInfo info;
  const auto p = metadata.find("parameterization");
  if (p == metadata.end() || !p->is_string()) throw missing("parameterization");
  if (*p == "profile" || isFresnelTableParameterization(*p)) {
    throw Error(Error::Kind::InvalidInput,
                std::string(*p == "profile" ? "a 1-D radial profile" : "a 1-D Fresnel table") +
                    ", not a 2-D map (brdfbake sample, info, convert and preview read it: "
                    "BakedOutput::open)");
  }
  info.parameterization = parseParameterizationKind(p->get<std::string>());
  const auto r = metadata.find("resolution");
  if (r == metadata.end() || !r->is_number_integer() || r->get<int>() < 1) throw missing("resolution");
  info.resolution = r->get<int>();
  const auto c = metadata.find("convention_version");
  if (c == metadata.end() || !c->is_number_integer()) throw missing("convention_version");
  info.conventionVersion = c->get<int>();
  if (info.conventionVersion > kConventionVersion) {
    throw Error(Error::Kind::InvalidInput, "map uses convention version " + std::to_string(info.conventionVersion) +
                                               ", newer than this brdfbake understands (" +
                                               std::to_string(kConventionVersion) + ")");
  }
  info.spec = metadataValue(metadata, "spec", nlohmann::json::object());
  if (!info.spec.is_object() && !info.spec.is_null()) throw missing("spec");  // null: made by a program, no spec
  return info;
}

bool isFresnelTableParameterization(const std::string& parameterization) {
  return parameterization == kFresnelTableParameterization || parameterization == "fresnel_profile";
}

LinearTaps linearTaps(int texels, double s) {
  const double x = std::clamp(s * texels - 0.5, 0.0, static_cast<double>(texels - 1));
  const int i0 = std::min(static_cast<int>(x), texels - 1), i1 = std::min(i0 + 1, texels - 1);
  return {i0, i1, x - i0};
}

Rgb sampleLinear1d(const std::vector<Rgb>& texels, double s) {
  if (texels.empty()) throw Error(Error::Kind::InvalidArgument, "a 1-D texture needs at least one texel");
  const LinearTaps taps = linearTaps(static_cast<int>(texels.size()), s);
  return (1.0 - taps.w) * texels[static_cast<std::size_t>(taps.i0)] +
         taps.w * texels[static_cast<std::size_t>(taps.i1)];
}

BilinearTaps bilinearTaps(const Vec2& pixel, const TexelRect& region, bool wrapX) {
  const double fx = pixel.x() - 0.5 - region.x0, fy = pixel.y() - 0.5 - region.y0;
  const double x0f = std::floor(fx), y0f = std::floor(fy);
  int xa, xb;
  if (wrapX) {
    xa = static_cast<int>(x0f) % region.width;
    if (xa < 0) xa += region.width;
    xb = xa + 1 == region.width ? 0 : xa + 1;
  } else {
    xa = std::clamp(static_cast<int>(x0f), 0, region.width - 1);
    xb = std::clamp(static_cast<int>(x0f) + 1, 0, region.width - 1);
  }
  const int ya = std::clamp(static_cast<int>(y0f), 0, region.height - 1);
  const int yb = std::clamp(static_cast<int>(y0f) + 1, 0, region.height - 1);
  return {region.x0 + xa, region.x0 + xb, region.y0 + ya, region.y0 + yb, fx - x0f, fy - y0f};
}

BilinearTaps bilinearTaps(const Parameterization& map, const Vec3& direction) {
  const MapAddress address = map.getAddressFor(direction);
  return bilinearTaps(address.pixel, map.region(address.region), map.wrapsHorizontally());
}

namespace {

Rgba blend(const Image& image, const BilinearTaps& t) {
  const double wx = t.wx, wy = t.wy;
  const float* p00 = image.data() + image.index(t.xa, t.ya);
  const float* p10 = image.data() + image.index(t.xb, t.ya);
  const float* p01 = image.data() + image.index(t.xa, t.yb);
  const float* p11 = image.data() + image.index(t.xb, t.yb);
  Rgba value;
  for (int k = 0; k < 4; ++k) {
    value[k] = (1 - wy) * ((1 - wx) * p00[k] + wx * p10[k]) + wy * ((1 - wx) * p01[k] + wx * p11[k]);
  }
  return value;
}

}  // namespace

Rgba sampleBilinear(const Image& image, const Vec2& pixel, const TexelRect& region, bool wrapX) {
  return blend(image, bilinearTaps(pixel, region, wrapX));
}

Rgba sampleBilinear(const Image& image, const Parameterization& map, const Vec3& direction) {
  require(image.width() == map.width() && image.height() == map.height(),
          "image size does not match the parameterization");
  return blend(image, bilinearTaps(map, direction));
}

Image fresnelTableImage(const std::vector<Rgb>& table) {
  require(!table.empty(), "a Fresnel table needs at least one texel");
  const int n = static_cast<int>(table.size());
  Image image(n, 1);
  for (int i = 0; i < n; ++i) {
    const Rgb& f = table[static_cast<std::size_t>(i)];
    image.set(i, 0, Rgba(f[0], f[1], f[2], 1.0));
  }
  image.metadata = {{"parameterization", kFresnelTableParameterization},
                    {"resolution", n},
                    {"convention_version", kConventionVersion},
                    {"coordinate", "F(cos theta), cos theta = n.v; texel i at cos theta = (i + 0.5) / " +
                                       std::to_string(n) + ": a linear lookup at s = n.v (clamp to edge) returns F"}};
  return image;
}

}  // namespace brdfbake
