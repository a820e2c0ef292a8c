#include <brdfbake/brdf/smith.hpp>
#include <brdfbake/core/named_values.hpp>

#include <array>

namespace brdfbake {

std::string_view toString(MicrofacetShadowing shadowing) {
  switch (shadowing) {
    case MicrofacetShadowing::VCavity:
      return "v_cavity";
    case MicrofacetShadowing::SmithCorrelated:
      return "smith_correlated";
    case MicrofacetShadowing::SmithSeparable:
      return "smith_separable";
  }
  return "?";
}

MicrofacetShadowing parseMicrofacetShadowing(std::string_view name) {
  return parseByName(name,
                     std::array{MicrofacetShadowing::VCavity, MicrofacetShadowing::SmithCorrelated,
                                MicrofacetShadowing::SmithSeparable},
                     "shadowing");
}

}  // namespace brdfbake
