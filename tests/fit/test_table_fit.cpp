// Half-difference tables fitted to measured tables (fit/table_fit.hpp, LobeKindChoice::HalfDifference,
// FitOptions::halfDifference): recovery of a known table on the Cornell grid, the automatic choice, fit.json.
#include <gtest/gtest.h>

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/held_out.hpp>
#include <brdfbake/fit/lobe_fit.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "../../fit/table_fit.hpp"

namespace brdfbake {
namespace {

// A table of the fitted shape whose coefficients are linear in knot k and degree j: the smoothness
// penalty (second differences) is 0 on it, so a fit of its exact values recovers it.
std::vector<double> linearCoefficients(double base, double perKnot, double perDegree) {
  const HalfDifferenceTableShape shape = detail::kFittedTableShape;
  std::vector<double> a;
  for (int k = 0; k < shape.halfAngleKnots; ++k)
    for (int j = 0; j <= shape.differenceDegree; ++j) a.push_back(base + perKnot * k + perDegree * j);
  return a;
}

// A highlight (ln f falling 0.45 per knot from 1.5, 1.0, 0.5) whose colour turns with theta_d.
LobeModel rgbTable() {
  LobeModel model;
  model.halfDifference = detail::kFittedTableShape;
  const double bases[3] = {1.5, 1.0, 0.5};
  for (int c = 0; c < 3; ++c) {
    LobeChannel channel;
    channel.name = std::string(1, "RGB"[c]);
    channel.halfDifferenceCoefficients = linearCoefficients(bases[c], -0.45, 0.15 * c);
    model.channels.push_back(channel);
  }
  model.validate();
  return model;
}

TEST(TableFit, RecoversATableTheGridSamples) {
  const LobeModel truth = rgbTable();
  FitOptions options;
  options.kind = LobeKindChoice::HalfDifference;
  options.estimateHeldOut = false;
  const FitResult fit = fitLobes(makeSyntheticTable(truth, 0.0, 1), options);
  ASSERT_TRUE(fit.model.hasHalfDifference());
  EXPECT_TRUE(fit.model.channels[0].lobes.empty());
  for (std::size_t c = 0; c < 3; ++c) {
    const auto& fitted = fit.model.channels[c].halfDifferenceCoefficients;
    const auto& known = truth.channels[c].halfDifferenceCoefficients;
    ASSERT_EQ(fitted.size(), known.size());
    for (std::size_t k = 0; k < known.size(); ++k)
      EXPECT_NEAR(fitted[k], known[k], 1e-5) << c << " " << k;  // 1e-9 ridge
  }
}

TEST(TableFit, ThePenaltyContinuesTheTableLinearlyWhereNoRowReaches) {
  // Only the grid's rows within 15 degrees of the half-vector's highlight (theta_h < 15 degrees: knots 0
  // to 5 of 12): the data determine nothing beyond. The penalty on second differences is 0 on
  // coefficients linear in the knot, so it continues them linearly there; a penalty on first
  // differences (or none, with the ridge) would hold them level or at 0. Slopes small enough that the
  // continued coefficients stay within the clamp (a factor e of the rows' values).
  LobeModel truth;
  truth.halfDifference = detail::kFittedTableShape;
  truth.channels.push_back({"Y", 0.0, {}, {}, linearCoefficients(1.5, -0.08, 0.1)});
  const MeasuredTable grid = makeSyntheticTable(truth, 0.0, 1);
  MeasuredTable near = grid;
  near.angles.clear();
  std::vector<Eigen::Index> kept;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const Vec3 h = (grid.incidentDirection(i) + grid.outgoingDirection(i)).normalized();
    if (h.z() > std::cos(15.0 * kPi / 180.0)) {
      near.angles.push_back(grid.angles[i]);
      kept.push_back(static_cast<Eigen::Index>(i));
    }
  }
  near.values = grid.values(kept, Eigen::all);
  ASSERT_GE(near.size(), 84u);
  FitOptions options;
  options.kind = LobeKindChoice::HalfDifference;
  options.estimateHeldOut = false;
  const FitResult fit = fitLobes(near, options);
  const auto& fitted = fit.model.channels[0].halfDifferenceCoefficients;
  const auto& known = truth.channels[0].halfDifferenceCoefficients;
  const int stride = detail::kFittedTableShape.differenceDegree + 1;
  for (int k = 6; k < detail::kFittedTableShape.halfAngleKnots; ++k)  // knots no row reaches
    for (int j = 0; j < stride; ++j)
      EXPECT_NEAR(fitted[static_cast<std::size_t>(k * stride + j)], known[static_cast<std::size_t>(k * stride + j)],
                  1e-4)
          << "knot " << k << " degree " << j;
}

TEST(TableFit, StaysWithinAFactorEOfTheValuesItWasFittedTo) {
  // ln f rising 2 per Bernstein degree in theta_d: towards theta_d = 90 degrees, where the Cornell grid
  // has no sample, the table made from it climbs above every sample. The fit stays within a factor e
  // (detail::kTableRangeMargin) of the samples' range everywhere.
  LobeModel truth;
  truth.halfDifference = detail::kFittedTableShape;
  truth.channels.push_back({"Y", 0.0, {}, {}, linearCoefficients(-4.0, -0.3, 2.0)});
  const MeasuredTable table = makeSyntheticTable(truth, 0.0, 1);
  const double largest = table.values.maxCoeff(), smallest = table.values.minCoeff();
  FitOptions options;
  options.kind = LobeKindChoice::HalfDifference;
  options.estimateHeldOut = false;
  const LobeModel fit = fitLobes(table, options).model;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const double ci = 0.01 + 0.99 * u(rng), co = 0.01 + 0.99 * u(rng), pi = 6.283 * u(rng), po = 6.283 * u(rng);
    const Vec3 l(std::sqrt(1 - ci * ci) * std::cos(pi), std::sqrt(1 - ci * ci) * std::sin(pi), ci);
    const Vec3 v(std::sqrt(1 - co * co) * std::cos(po), std::sqrt(1 - co * co) * std::sin(po), co);
    const double f = fit.evaluate(0, l, v);
    ASSERT_LE(f, std::exp(1.0) * largest * (1 + 1e-12));
    ASSERT_GE(f, std::exp(-1.0) * smallest * (1 - 1e-12));
  }
  // At the grazing mirror direction the table it was made from (what an unclamped fit of these exact
  // samples extrapolates to) leaves that range: the clamp has work to do.
  const double c = std::cos(radians(89.9)), s = std::sin(radians(89.9));
  EXPECT_GT(truth.evaluate(0, Vec3(s, 0.0, c), Vec3(-s, 0.0, c)), 1.5 * std::exp(1.0) * largest);
  EXPECT_LE(fit.evaluate(0, Vec3(s, 0.0, c), Vec3(-s, 0.0, c)), std::exp(1.0) * largest * (1 + 1e-12));
}

TEST(TableFit, AutoChoosesATableOnlyWhereItPredictsBetter) {
  // A table the lobes cannot follow (a highlight with a colour that turns with theta_d), 2 % noise:
  // auto keeps a table, and its held-out score is the table candidate's. A table made from two mirror
  // lobes: auto keeps the lobes, with the table scored and listed.
  FitOptions options;
  options.maxAutoLobes = 2;
  const FitResult onTable = fitLobes(makeSyntheticTable(rgbTable(), 0.02, 3), options);
  ASSERT_TRUE(onTable.heldOut);
  EXPECT_TRUE(onTable.model.hasHalfDifference()) << onTable.briefReport();
  const ModelCandidate* table = nullptr;
  for (const auto& c : onTable.candidates)
    if (c.kind == LobeKindChoice::HalfDifference) table = &c;
  ASSERT_NE(table, nullptr);
  EXPECT_LT(onTable.heldOut->score(), 0.5);

  LobeModel lobes;
  for (int c = 0; c < 3; ++c) {
    LobeChannel channel;
    channel.name = std::string(1, "RGB"[c]);
    channel.diffuse = 0.05 + 0.1 * c;
    channel.lobes = {Lobe{{0.3}, {800.0}}, Lobe{{0.2}, {20.0}}};
    lobes.channels.push_back(channel);
  }
  const FitResult onLobes = fitLobes(makeSyntheticTable(lobes, 0.01, 4), options);
  EXPECT_FALSE(onLobes.model.hasHalfDifference()) << onLobes.briefReport();
  int tables = 0;
  for (const auto& c : onLobes.candidates) tables += c.kind == LobeKindChoice::HalfDifference;
  EXPECT_EQ(tables, 1);
  options.halfDifference = false;
  for (const auto& c : fitLobes(makeSyntheticTable(lobes, 0.01, 4), options).candidates)
    EXPECT_NE(c.kind, LobeKindChoice::HalfDifference);
  options.halfDifference = true;
  options.kind = LobeKindChoice::Mirror;  // an explicit kind: those lobes, no table
  for (const auto& c : fitLobes(makeSyntheticTable(lobes, 0.01, 4), options).candidates)
    EXPECT_NE(c.kind, LobeKindChoice::HalfDifference);
}

TEST(TableFit, TheTableCandidateScoresAsItsOwnFit) {
  const MeasuredTable table = makeSyntheticTable(rgbTable(), 0.02, 5);
  FitOptions options;
  options.maxAutoLobes = 1;
  const FitResult automatic = fitLobes(table, options);
  options.kind = LobeKindChoice::HalfDifference;
  const FitResult alone = fitLobes(table, options);
  ASSERT_TRUE(alone.heldOut);
  bool found = false;
  for (const auto& c : automatic.candidates) {
    if (c.kind != LobeKindChoice::HalfDifference) continue;
    found = true;
    EXPECT_NEAR(c.heldOutScore, alone.heldOut->score(), 1e-9);
    EXPECT_EQ(c.lobes, 0);
    EXPECT_FALSE(c.radiallySymmetric());
  }
  EXPECT_TRUE(found);
}

TEST(TableFit, ASmallTableIsFittedWithoutOne) {
  // 60 rows: enough for the lobes' held-out splits, too few for the table's 84 coefficients per channel.
  // The default fit leaves the table out; asking for it is an error that says why.
  const MeasuredTable full = makeSyntheticTable(rgbTable(), 0.02, 6);
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < full.size() && rows.size() < 60; i += full.size() / 60) rows.push_back(i);
  const MeasuredTable small = tableRows(full, rows);
  FitOptions options;
  options.maxAutoLobes = 1;
  const FitResult fit = fitLobes(small, options);
  EXPECT_FALSE(fit.model.hasHalfDifference());
  for (const auto& c : fit.candidates) EXPECT_NE(c.kind, LobeKindChoice::HalfDifference);
  options.kind = LobeKindChoice::HalfDifference;
  try {
    fitLobes(small, options);
    FAIL() << "84 coefficients fitted to 60 rows";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot determine a half-difference table of 84 coefficients"),
              std::string::npos)
        << e.what();
  }
}

TEST(TableFit, OptionsThatATableCannotHonourAreRefused) {
  const MeasuredTable table = makeSyntheticTable(rgbTable(), 0.0, 1);
  FitOptions options;
  options.kind = LobeKindChoice::HalfDifference;
  options.lobes = 2;
  EXPECT_THROW(fitLobes(table, options), Error);
  options.lobes = 0;
  options.method = FitMethod::PerChannel;
  EXPECT_THROW(fitLobes(table, options), Error);
  options.method = FitMethod::Shared;
  options.elevation = ElevationChoice::Varying;
  EXPECT_THROW(fitLobes(table, options), Error);
}

TEST(TableFit, FitJsonKeepsTablesAndNamesWhatIsWrong) {
  {
    FitFile file;
    file.fit.model = rgbTable();
    file.hasSource = file.hasFitInfo = false;
    const nlohmann::json document = nlohmann::json::parse(fitFileToJson(file).dump());
    const LobeModel read = fitFileFromJson(document, "fit.json").fit.model;
    EXPECT_EQ(read.halfDifference.halfAngleKnots, 12);
    EXPECT_EQ(read.halfDifference.differenceDegree, 6);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.7, 0.7);
    for (int i = 0; i < 200; ++i) {
      const Vec3 l = Vec3(u(rng), u(rng), 1.0).normalized(), v = Vec3(u(rng), u(rng), 1.0).normalized();
      ASSERT_EQ(read.evaluate(l, v), file.fit.model.evaluate(l, v));
    }
    const auto message = [](const nlohmann::json& bad) {
      try {
        fitFileFromJson(bad, "fit.json");
      } catch (const Error& e) {
        return std::string(e.what());
      }
      return std::string("accepted");
    };
    nlohmann::json bad = document;
    bad["channels"][1]["half_difference"].erase(0);
    EXPECT_NE(message(bad).find("fit.json: channels[1].half_difference: must hold 84 number(s), got 83"),
              std::string::npos)
        << message(bad);
    bad = document;
    bad["channels"][0]["half_difference"][5] = 60.0;
    EXPECT_NE(message(bad).find("fit.json: channels[0].half_difference[5]: must be <= 50"), std::string::npos)
        << message(bad);
    bad = document;
    bad["model"].erase("half_difference");
    EXPECT_NE(message(bad).find(
                  "fit.json: channels[0].half_difference: coefficients of a half-difference table the model has not"),
              std::string::npos)
        << message(bad);
    bad = document;
    bad["channels"][2]["diffuse"] = 0.1;
    EXPECT_NE(message(bad).find("channel 'B': a half-difference table has no diffuse term and no lobes"),
              std::string::npos)
        << message(bad);
    bad = document;
    bad["model"]["half_difference"]["half_angle_knots"] = 1;
    EXPECT_NE(message(bad).find("fit.json: model.half_difference.half_angle_knots"), std::string::npos) << message(bad);
  }
}

}  // namespace
}  // namespace brdfbake
