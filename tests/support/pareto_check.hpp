#pragma once
// The Pareto front of a chart, recomputed from its points (independently of `brdfbake chart`).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace brdfbake::test {

/// Checks every point's "pareto" flag against non-dominance recomputed from "seconds" and
/// `errorKey`: a point is on the front unless another is no slower and no less accurate, and
/// strictly better in one of the two.
inline void expectParetoFlagsMatch(const nlohmann::json& points, const char* errorKey = "rms") {
  for (const auto& p : points) {
    const double t = p["seconds"].get<double>(), e = p[errorKey].get<double>();
    bool dominated = false;
    for (const auto& o : points) {
      const double to = o["seconds"].get<double>(), eo = o[errorKey].get<double>();
      dominated = dominated || (to <= t && eo <= e && (to < t || eo < e));
    }
    EXPECT_EQ(p["pareto"].get<bool>(), !dominated) << p.dump();
  }
}

}  // namespace brdfbake::test
