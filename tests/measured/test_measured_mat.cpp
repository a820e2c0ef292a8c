// MATLAB .mat tables: files written here with libmatio in Cornell's variable layout.
#include <brdfbake/measured/measured_io.hpp>

#include "measured_test_files.hpp"
#include "test_support.hpp"

#include <matio.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>

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

// ---- the structure of a level-5 file, built byte by byte (MAT-File Format, 2021, chapter 1) ---------

std::string le32(std::uint32_t v) {
  return {static_cast<char>(v), static_cast<char>(v >> 8), static_cast<char>(v >> 16), static_cast<char>(v >> 24)};
}
std::string matHeader() {
  std::string header = "MATLAB 5.0 MAT-file, written by hand";
  header.resize(116, ' ');
  return header + std::string(8, '\0') + std::string("\x00\x01IM", 4);
}
std::string padded(std::string bytes) {
  bytes.resize((bytes.size() + 7) / 8 * 8, '\0');
  return bytes;
}
std::string element(std::uint32_t type, const std::string& data) {
  return le32(type) + le32(static_cast<std::uint32_t>(data.size())) + padded(data);
}
// A miMATRIX of class `arrayClass` and dimensions rows x cols named "junk", then `rest`.
std::string array(std::uint32_t arrayClass, std::uint32_t rows, std::uint32_t cols, const std::string& rest) {
  const std::string flags = element(6, le32(arrayClass) + le32(0));
  const std::string dims = element(5, le32(rows) + le32(cols));
  const std::string name = le32((4u << 16) | 1u) + "junk";  // a small data element
  return element(14, flags + dims + name + rest);
}
const std::string kEmptyCell = le32(14) + le32(0);

std::string compressed(const std::string& bytes) {
  uLongf size = compressBound(bytes.size());
  std::string out(size, '\0');
  EXPECT_EQ(
      compress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()), bytes.size()),
      Z_OK);
  out.resize(size);
  return le32(15) + le32(static_cast<std::uint32_t>(out.size())) + out;
}

TEST_F(MalformedMat, CellsTheFileCannotHoldAreRefusedBeforeLibmatioAllocatesThem) {
  // 672 bytes that claim 50000 x 50000 cells took libmatio 129 s (20 GB of cell pointers per lookup).
  const std::string junk = array(1, 50000, 50000, kEmptyCell);
  for (const std::string& variable : {junk, compressed(junk)}) {
    test::writeFile(dir_ / "bad.mat", matHeader() + variable);
    EXPECT_TRUE(rejects([&] { readMat(dir_ / "bad.mat"); }, {name(), "claims 2500000000 cells, more than its"}));
  }
  // Structs: elements times fields (a field name length of 8, two names "a" and "b").
  const std::string fieldNames =
      le32((4u << 16) | 5u) + le32(8) + element(1, std::string("a\0\0\0\0\0\0\0b\0\0\0\0\0\0\0", 16));
  test::writeFile(dir_ / "bad.mat", matHeader() + array(2, 40000, 40000, fieldNames));
  EXPECT_TRUE(rejects([&] { readMat(dir_ / "bad.mat"); }, {name(), "claims 3200000000 struct fields"}));
}

TEST_F(MalformedMat, NumbersTheirDataCannotHoldAreRefused) {
  // 50331648 x 4 doubles claimed over 48 bytes of data (libmatio allocated and zero-filled 800 MB).
  test::writeFile(dir_ / "bad.mat", matHeader() + array(6, 50331648, 4, element(9, std::string(48, '\0'))));
  EXPECT_TRUE(
      rejects([&] { readMat(dir_ / "bad.mat"); }, {name(), "claims 201326592 values, but its real part holds 6"}));
}

TEST_F(MalformedMat, NestedTagsMustLieWithinTheirArray) {
  // The array is 56 bytes long, its dimensions tag claims 0x702d3408.
  const std::string variable =
      le32(14) + le32(48) + element(6, le32(6) + le32(0)) + le32(5) + le32(0x702d3408) + std::string(24, '\0');
  test::writeFile(dir_ / "bad.mat", matHeader() + variable);
  EXPECT_TRUE(rejects([&] { readMat(dir_ / "bad.mat"); },
                      {name(), "an array's dimensions at byte", "only 24 follow within its parent"}));
}

TEST_F(MalformedMat, CellsNestAtMost32Deep) {
  std::string cell = kEmptyCell;
  for (int depth = 0; depth < 40; ++depth) cell = array(1, 1, 1, cell);
  test::writeFile(dir_ / "bad.mat", matHeader() + cell);
  EXPECT_TRUE(rejects([&] { readMat(dir_ / "bad.mat"); }, {name(), "nested more than 32 deep"}));
}

TEST_F(MalformedMat, CellsAndStructsLibmatioWroteStillRead) {
  // A valid table with a cell array and a struct beside it: both walked, neither refused.
  const auto path = dir_ / "ok.mat";
  ASSERT_TRUE(writeMat(path, {{"dir_in", dirIn2()}, {"dir_out", dirOut2()}, {"fr", frValues(3)}}));
  mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDWR);
  ASSERT_NE(mat, nullptr);
  size_t dims[2] = {2, 1};
  double value = 1.5;
  size_t one[2] = {1, 1};
  matvar_t* cells[2] = {Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &value, 0),
                        Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &value, 0)};
  matvar_t* cell = Mat_VarCreate("notes", MAT_C_CELL, MAT_T_CELL, 2, dims, cells, 0);
  const char* fieldNames[2] = {"a", "b"};
  matvar_t* structure = Mat_VarCreateStruct("info", 2, one, fieldNames, 2);
  Mat_VarSetStructFieldByName(structure, "a", 0, Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &value, 0));
  EXPECT_EQ(Mat_VarWrite(mat, cell, MAT_COMPRESSION_ZLIB), 0);
  EXPECT_EQ(Mat_VarWrite(mat, structure, MAT_COMPRESSION_NONE), 0);
  Mat_VarFree(cell);
  Mat_VarFree(structure);
  Mat_Close(mat);
  EXPECT_EQ(readMat(path).values, frValues(3));
}

TEST_F(MalformedMat, NotAMatFile) {
  test::writeFile(dir_ / "bad.mat", "MATLAB 5.0 MAT-file, but then nothing");
  EXPECT_TRUE(rejects([&] { readMat(dir_ / "bad.mat"); }, {name(), "not a MATLAB .mat file"}));
}

}  // namespace
}  // namespace brdfbake
