// MERL .binary: a synthetic full-size file with known numbers in every bin (33 MB in a temp dir).
#include <brdfbake/measured/measured_io.hpp>

#include "measured_test_files.hpp"
#include "test_support.hpp"

#include <Eigen/Geometry>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>

namespace brdfbake {
namespace {

using test::rejects;

constexpr std::size_t kBins = MerlTable::kBinsPerChannel;
constexpr std::uintmax_t kFileBytes = 12 + 3 * 8 * kBins;

// A distinct whole number per channel and bin: channel c, bin (th, td, pd) -> c.th td pd.
double storedNumber(int channel, int thetaHalf, int thetaDiff, int phiDiff) {
  return (channel + 1) * 1e7 + thetaHalf * 1e5 + thetaDiff * 1e3 + phiDiff;
}

// One bin (theta_half 5, theta_diff 7, phi_diff 9) is unmeasured in blue only.
constexpr int kHole[3] = {5, 7, 9};

std::vector<double> syntheticNumbers() {
  std::vector<double> numbers(3 * kBins);
  for (int c = 0; c < 3; ++c)
    for (int th = 0; th < 90; ++th)
      for (int td = 0; td < 90; ++td)
        for (int pd = 0; pd < 180; ++pd) numbers[c * kBins + pd + 180 * (td + 90 * th)] = storedNumber(c, th, td, pd);
  numbers[2 * kBins + kHole[2] + 180 * (kHole[1] + 90 * kHole[0])] = -1.0;
  return numbers;
}

void writeMerl(const std::filesystem::path& path, const std::int32_t dims[3], const std::vector<double>& numbers) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(dims), 12);
  out.write(reinterpret_cast<const char*>(numbers.data()),
            static_cast<std::streamsize>(numbers.size() * sizeof(double)));
}

// wi, wo whose Rusinkiewicz coordinates are the given ones (the inverse of MERL's mapping).
std::pair<Vec3, Vec3> fromHalfDiff(double thetaHalf, double phiHalf, double thetaDiff, double phiDiff) {
  const Vec3 d = directionFromAngles(thetaDiff, phiDiff);
  const Mat3 toWorld =
      (Eigen::AngleAxisd(phiHalf, Vec3::UnitZ()) * Eigen::AngleAxisd(thetaHalf, Vec3::UnitY())).toRotationMatrix();
  return {toWorld * d, toWorld * Vec3(-d.x(), -d.y(), d.z())};
}

class MerlFile : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<test::TempDir>();
    const std::int32_t dims[3] = {90, 90, 180};
    writeMerl(*dir_ / "synthetic.binary", dims, syntheticNumbers());
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static std::filesystem::path file() { return *dir_ / "synthetic.binary"; }
  static std::unique_ptr<test::TempDir> dir_;
};
std::unique_ptr<test::TempDir> MerlFile::dir_;

void expectBin(const MerlTable& table, const Vec3& wi, const Vec3& wo, int th, int td, int pd) {
  const std::optional<Rgb> value = table.evaluate(wi, wo);
  ASSERT_TRUE(value.has_value());
  EXPECT_DOUBLE_EQ((*value)[0], storedNumber(0, th, td, pd) * 1.0 / 1500.0);
  EXPECT_DOUBLE_EQ((*value)[1], storedNumber(1, th, td, pd) * 1.15 / 1500.0);
  EXPECT_DOUBLE_EQ((*value)[2], storedNumber(2, th, td, pd) * 1.66 / 1500.0);
}

TEST_F(MerlFile, SizeAndDetection) {
  EXPECT_EQ(std::filesystem::file_size(file()), kFileBytes);
  EXPECT_EQ(kFileBytes, 34992012u);
  EXPECT_EQ(detectTableFormat(file()), TableFormat::Merl);
  EXPECT_TRUE(rejects([&] { readMeasuredTable(file()); }, {file().string(), "readMerl"}));
}

TEST_F(MerlFile, EvaluateLooksUpTheStandardBins) {
  const MerlTable table = readMerl(file());
  EXPECT_EQ(table.sourceFile(), file().string());
  EXPECT_EQ(table.unmeasuredBinCount(), 1u);

  // Normal incidence and view: every coordinate is 0.
  expectBin(table, Vec3::UnitZ(), Vec3::UnitZ(), 0, 0, 0);

  // The mirror direction at 30.5 degrees: theta_half = 0, theta_diff = 30.5 -> bin 30.
  const Vec3 light = directionFromAngles(radians(30.5), 0.0);
  expectBin(table, light, reflect<double>(light, Vec3::UnitZ()), 0, 30, 0);

  // theta_half 20 deg -> sqrt(20 / 90 * 90 * 90) = 42.4 -> bin 42 (the sqrt mapping); theta_diff
  // 35.5 -> 35; phi_diff 100.3 -> 100.
  auto [wi, wo] = fromHalfDiff(radians(20), radians(60), radians(35.5), radians(100.3));
  const MerlTable::HalfDiff hd = MerlTable::halfDiffCoordinates(wi, wo);
  EXPECT_NEAR(degrees(hd.thetaHalf), 20.0, 1e-9);
  EXPECT_NEAR(degrees(hd.phiHalf), 60.0, 1e-9);
  EXPECT_NEAR(degrees(hd.thetaDiff), 35.5, 1e-9);
  EXPECT_NEAR(degrees(hd.phiDiff), 100.3, 1e-9);
  expectBin(table, wi, wo, 42, 35, 100);

  // Reciprocity: phi_diff -79.7 deg is phi_diff 100.3 deg.
  std::tie(wi, wo) = fromHalfDiff(radians(20), radians(-45), radians(35.5), radians(-79.7));
  expectBin(table, wi, wo, 42, 35, 100);

  // theta_half 60 deg -> sqrt(5400) = 73.5 -> 73; theta_diff 10.2 -> 10; phi_diff 1.5 -> 1.
  std::tie(wi, wo) = fromHalfDiff(radians(60), radians(170), radians(10.2), radians(1.5));
  expectBin(table, wi, wo, 73, 10, 1);
}

TEST_F(MerlFile, UnmeasuredAndBelowHorizonAreNullopt) {
  const MerlTable table = readMerl(file());
  // Bin centres of the hole: theta_half index 5 starts at (5 / 90)^2 * 90 deg.
  const double thetaHalf = radians((5.5 * 5.5) / 90.0), thetaDiff = radians(7.5), phiDiff = radians(9.5);
  const auto [wi, wo] = fromHalfDiff(thetaHalf, 0.3, thetaDiff, phiDiff);
  ASSERT_EQ(MerlTable::thetaHalfIndex(thetaHalf), kHole[0]);
  EXPECT_FALSE(table.evaluate(wi, wo).has_value());
  EXPECT_FALSE(table.bin(kHole[0], kHole[1], kHole[2]).has_value());
  EXPECT_TRUE(table.bin(kHole[0], kHole[1], kHole[2] + 1).has_value());
  EXPECT_FALSE(table.evaluate(Vec3(0.3, 0.0, -0.9), Vec3::UnitZ()).has_value());
  EXPECT_FALSE(table.evaluate(Vec3::UnitZ(), Vec3(1.0, 0.0, 0.0)).has_value());
}

TEST(MerlIndex, StandardIndexFunctions) {
  EXPECT_EQ(MerlTable::thetaHalfIndex(0.0), 0);
  EXPECT_EQ(MerlTable::thetaHalfIndex(-0.1), 0);
  EXPECT_EQ(MerlTable::thetaHalfIndex(radians(1.0)), 9);  // sqrt(90) = 9.49
  EXPECT_EQ(MerlTable::thetaHalfIndex(radians(89.9)), 89);
  EXPECT_EQ(MerlTable::thetaHalfIndex(radians(95.0)), 89);
  EXPECT_EQ(MerlTable::thetaDiffIndex(radians(45.0)), 45);
  EXPECT_EQ(MerlTable::thetaDiffIndex(radians(90.0)), 89);
  EXPECT_EQ(MerlTable::phiDiffIndex(radians(179.9)), 179);
  EXPECT_EQ(MerlTable::phiDiffIndex(kPi), 179);
  EXPECT_EQ(MerlTable::phiDiffIndex(radians(-0.5)), 179);
  EXPECT_EQ(MerlTable::phiDiffIndex(radians(-179.5)), 0);
}

TEST(ReadMerl, WrongSizeIsRejectedBeforeReading) {
  test::TempDir dir;
  const std::int32_t dims[3] = {90, 90, 180};
  writeMerl(dir / "short.binary", dims, std::vector<double>(1000, 1.0));
  EXPECT_TRUE(rejects([&] { readMerl(dir / "short.binary"); },
                      {(dir / "short.binary").string() + ": ", "must be exactly 34992012 bytes", "has 8012"}));
  std::vector<double> almost(3 * kBins - 1, 1.0);
  writeMerl(dir / "almost.binary", dims, almost);
  EXPECT_TRUE(rejects([&] { readMerl(dir / "almost.binary"); }, {"almost.binary", "has 34992004"}));
  EXPECT_TRUE(test::throwsError([&] { readMerl(dir / "absent.binary"); }, Error::Kind::Io, {"absent.binary"}));
}

TEST(ReadMerl, WrongDimsAndNanAreRejected) {
  test::TempDir dir;
  std::vector<double> numbers(3 * kBins, 1.0);
  const std::int32_t otherDims[3] = {180, 90, 90};  // right size, wrong order
  writeMerl(dir / "dims.binary", otherDims, numbers);
  EXPECT_TRUE(
      rejects([&] { readMerl(dir / "dims.binary"); }, {"dims.binary", "180 x 90 x 90, expected 90 x 90 x 180"}));

  const std::int32_t dims[3] = {90, 90, 180};
  numbers[kBins + 181] = std::nan("");  // green, theta_half 0, theta_diff 1, phi_diff 1
  writeMerl(dir / "nan.binary", dims, numbers);
  EXPECT_TRUE(rejects([&] { readMerl(dir / "nan.binary"); },
                      {"nan.binary", "non-finite", "byte " + std::to_string(12 + 8 * (kBins + 181)), "channel G",
                       "theta_diff bin 1, phi_diff bin 1"}));
}

}  // namespace
}  // namespace brdfbake
