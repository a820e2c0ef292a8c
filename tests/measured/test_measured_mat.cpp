// MATLAB .mat tables: files written here with libmatio in Cornell's variable layout.
#include <brdfbake/measured/measured_io.hpp>

#include "measured_test_files.hpp"
#include "test_support.hpp"

#include <matio.h>

#include <cmath>

namespace brdfbake {
namespace {

using test::rejects;

using Variables = std::vector<std::pair<std::string, Eigen::MatrixXd>>;

// Writes real double matrices (column-major, as MATLAB stores them). False if matio cannot
// create this file version (v7.3 needs matio built with HDF5).
bool writeMat(const std::filesystem::path& path, const Variables& variables, mat_ft version = MAT_FT_MAT5) {
  mat_t* mat = Mat_CreateVer(path.string().c_str(), nullptr, version);
  if (!mat) return false;
  for (const auto& [name, matrix] : variables) {
    Eigen::MatrixXd copy = matrix;
    size_t dims[2] = {static_cast<size_t>(copy.rows()), static_cast<size_t>(copy.cols())};
    matvar_t* var = Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, copy.data(), 0);
    EXPECT_NE(var, nullptr);
    EXPECT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE), 0);
    Mat_VarFree(var);
  }
  Mat_Close(mat);
  return true;
}

// Three samples: theta_i 10/20/30 deg, phi_i 0, theta_s 15 deg, phi_s pi, -pi/2, 0.
Eigen::MatrixXd dirIn2() {
  Eigen::MatrixXd m(3, 2);
  m << radians(10), 0, radians(20), 0, radians(30), 0;
  return m;
}
Eigen::MatrixXd dirOut2() {
  Eigen::MatrixXd m(3, 2);
  m << radians(15), kPi, radians(15), -kPi / 2, radians(15), 0;
  return m;
}
// fr(r, c) = (r + 1) + c / 100.
Eigen::MatrixXd frValues(int channels) {
  Eigen::MatrixXd m(3, channels);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < channels; ++c) m(r, c) = (r + 1) + c / 100.0;
  return m;
}

TEST(ReadMat, SpectralWithAngles) {
  test::TempDir dir;
  Eigen::MatrixXd wavelength(1, 4);
  wavelength << 400, 500, 600, 700;
  ASSERT_TRUE(writeMat(
      dir / "t.mat", {{"dir_in", dirIn2()}, {"dir_out", dirOut2()}, {"fr", frValues(4)}, {"wavelength", wavelength}}));
  EXPECT_EQ(detectTableFormat(dir / "t.mat"), TableFormat::Mat);
  const MeasuredTable table = readMeasuredTable(dir / "t.mat");
  EXPECT_EQ(table.format, TableFormat::Mat);
  EXPECT_EQ(table.kind, ChannelKind::Spectral);
  EXPECT_EQ(table.wavelengthsNm, (std::vector<double>{400, 500, 600, 700}));
  EXPECT_EQ(table.channelNames.front(), "400nm");
  ASSERT_EQ(table.size(), 3u);
  EXPECT_EQ(table.values, frValues(4));
  EXPECT_DOUBLE_EQ(table.angles[1].thetaIn, radians(20));
  EXPECT_DOUBLE_EQ(table.angles[0].phiOut, kPi);
  EXPECT_DOUBLE_EQ(table.angles[1].phiOut, -kPi / 2);
  EXPECT_EQ(table.incidentThetas().size(), 3u);
}

TEST(ReadMat, UnitVectorsRgb) {
  test::TempDir dir;
  Eigen::MatrixXd in(3, 3), out(3, 3);
  for (int r = 0; r < 3; ++r) {
    in.row(r) = directionFromAngles(dirIn2()(r, 0), dirIn2()(r, 1)).transpose();
    out.row(r) = directionFromAngles(dirOut2()(r, 0), dirOut2()(r, 1)).transpose();
  }
  ASSERT_TRUE(writeMat(dir / "v.mat", {{"dir_in", in}, {"dir_out", out}, {"fr", frValues(3)}}));
  const MeasuredTable table = readMat(dir / "v.mat");
  EXPECT_EQ(table.kind, ChannelKind::Trichromatic);
  EXPECT_EQ(table.channelNames, (std::vector<std::string>{"R", "G", "B"}));
  for (int r = 0; r < 3; ++r) {
    EXPECT_NEAR(table.angles[r].thetaIn, dirIn2()(r, 0), 1e-12);
    EXPECT_NEAR(table.angles[r].thetaOut, dirOut2()(r, 0), 1e-12);
    EXPECT_TRUE(table.outgoingDirection(r).isApprox(out.row(r).transpose(), 1e-12));
  }
  EXPECT_NEAR(std::abs(table.angles[0].phiOut), kPi, 1e-12);
}

TEST(ReadMat, AllFourAnglesInDirInMonochrome) {
  test::TempDir dir;
  Eigen::MatrixXd all(3, 4);
  all << dirIn2(), dirOut2();
  ASSERT_TRUE(writeMat(dir / "m.mat", {{"dir_in", all}, {"fr", frValues(1)}}));
  const MeasuredTable table = readMat(dir / "m.mat");
  EXPECT_EQ(table.kind, ChannelKind::Monochrome);
  EXPECT_EQ(table.channelCount(), 1u);
  EXPECT_DOUBLE_EQ(table.angles[2].thetaIn, radians(30));
  EXPECT_DOUBLE_EQ(table.angles[1].phiOut, -kPi / 2);
  EXPECT_EQ(table.values(2, 0), 3.0);
}

TEST(ReadMat, Version73WhenMatioHasHdf5) {
  test::TempDir dir;
  if (!writeMat(dir / "h.mat", {{"dir_in", dirIn2()}, {"dir_out", dirOut2()}, {"fr", frValues(3)}}, MAT_FT_MAT73))
    GTEST_SKIP() << "libmatio was built without HDF5 (MAT v7.3)";
  EXPECT_EQ(detectTableFormat(dir / "h.mat"), TableFormat::Mat);
  EXPECT_EQ(readMat(dir / "h.mat").values, frValues(3));
}

class MalformedMat : public ::testing::Test {
 protected:
  std::filesystem::path write(const Variables& variables) {
    const auto path = dir_ / "bad.mat";
    std::filesystem::remove(path);
    EXPECT_TRUE(writeMat(path, variables));
    return path;
  }
  std::string name() const { return (dir_ / "bad.mat").string() + ": "; }
  test::TempDir dir_;
};

TEST_F(MalformedMat, MissingVariables) {
  auto path = write({{"dir_in", dirIn2()}, {"dir_out", dirOut2()}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "variable 'fr' is missing"}));
  path = write({{"dir_in", dirIn2()}, {"fr", frValues(3)}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "variable 'dir_out' is missing"}));
}

TEST_F(MalformedMat, NanField) {
  Eigen::MatrixXd fr = frValues(3);
  fr(1, 2) = std::nan("");
  const auto path = write({{"dir_in", dirIn2()}, {"dir_out", dirOut2()}, {"fr", fr}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "variable 'fr' row 2 column 3 is not finite"}));
}

TEST_F(MalformedMat, ShapeMismatches) {
  auto path = write({{"dir_in", dirIn2()}, {"dir_out", dirOut2()}, {"fr", frValues(3).topRows(2)}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "'fr' has 2 rows for 3 directions"}));
  path = write({{"dir_in", dirIn2()}, {"dir_out", dirOut2()}, {"fr", frValues(5)}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "5 channels but there is no 'wavelength'"}));
  Eigen::MatrixXd wavelength(1, 2);
  wavelength << 400, 500;
  path = write({{"dir_in", dirIn2()}, {"dir_out", dirOut2()}, {"fr", frValues(3)}, {"wavelength", wavelength}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "'wavelength' must be a vector of 3 wavelengths"}));
  path = write({{"dir_in", dirIn2().transpose()}, {"dir_out", dirOut2()}, {"fr", frValues(3)}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "'dir_in' has 2 rows but 'dir_out' has 3"}));
  path = write({{"dir_in", Eigen::MatrixXd::Zero(3, 5)}, {"dir_out", dirOut2()}, {"fr", frValues(3)}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "'dir_in' must be N x 2", "is 3 x 5"}));
  Eigen::MatrixXd notUnit = Eigen::MatrixXd::Constant(3, 3, 0.9);
  path = write({{"dir_in", notUnit}, {"dir_out", dirOut2()}, {"fr", frValues(3)}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "'dir_in' row 1 is not a unit vector"}));
  Eigen::MatrixXd degreesIn = dirIn2() * (180.0 / kPi);
  path = write({{"dir_in", degreesIn}, {"dir_out", dirOut2()}, {"fr", frValues(3)}});
  EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "sample 1: theta_i = 10 is outside [0, pi/2]"}));
}

TEST_F(MalformedMat, TruncatedFilesAreRefusedEvenWhenLibmatioReadsThem) {
  // 100 samples so the cut falls inside 'fr', the last variable: libmatio alone reads the missing
  // rows as zeros.
  Eigen::MatrixXd in(100, 2), out(100, 2);
  for (int i = 0; i < 100; ++i) in.row(i) << radians(0.8 * i), 0.0, out.row(i) << radians(0.5 * i), kPi;
  const auto path = write({{"dir_in", in}, {"dir_out", out}, {"fr", Eigen::MatrixXd::Constant(100, 3, 0.5)}});
  ASSERT_EQ(readMat(path).size(), 100u);
  const auto size = std::filesystem::file_size(path);
  for (std::uintmax_t cut : {std::uintmax_t{300}, std::uintmax_t{1}, size - 130}) {
    std::filesystem::resize_file(path, size - cut);
    EXPECT_TRUE(rejects([&] { readMat(path); }, {name(), "truncated"})) << "cut " << cut << " bytes";
    std::filesystem::remove(path);
    write({{"dir_in", in}, {"dir_out", out}, {"fr", Eigen::MatrixXd::Constant(100, 3, 0.5)}});
  }
}

TEST_F(MalformedMat, NotAMatFile) {
  test::writeFile(dir_ / "bad.mat", "MATLAB 5.0 MAT-file, but then nothing");
  EXPECT_TRUE(rejects([&] { readMat(dir_ / "bad.mat"); }, {name(), "not a MATLAB .mat file"}));
}

}  // namespace
}  // namespace brdfbake
