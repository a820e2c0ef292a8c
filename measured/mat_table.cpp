// MATLAB .mat tables through libmatio.
#include <brdfbake/measured/measured_io.hpp>

#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/io/files.hpp>

#include "mat_structure.hpp"
#include "measured_common.hpp"

#include <matio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <tuple>

namespace brdfbake {

using measured::malformed;

namespace {

// libmatio reports problems through a log function that prints by default; the library must not
// print, so its messages are kept (per thread) and quoted in our errors instead.
thread_local std::string lastMatioMessage;

void keepMatioMessage(int, char* message) { lastMatioMessage = message ? message : ""; }

void silenceMatio() {
  static std::once_flag once;
  std::call_once(once, [] { Mat_LogInitFunc("brdfbake", keepMatioMessage); });
}

struct MatCloser {
  void operator()(mat_t* mat) const { Mat_Close(mat); }
};
struct VarFreer {
  void operator()(matvar_t* var) const { Mat_VarFree(var); }
};

// A real 2-D numeric variable as rows x cols (MATLAB stores columns one after another).
// `fileBytes` bounds what its dimensions may claim: libmatio allocates dims[0] x dims[1] values and
// reads a shorter data element as if the rest were zeros, so a 480-byte file could make it (and the
// copy here) allocate gigabytes. Each value takes at least one stored byte (zlib, for compressed
// variables, expands at most about 1032:1), and both copies must fit the memory budget.
Eigen::MatrixXd readMatrix(mat_t* mat, const char* name, const std::string& file, std::uintmax_t fileBytes) {
  lastMatioMessage.clear();
  {
    std::unique_ptr<matvar_t, VarFreer> info(Mat_VarReadInfo(mat, name));
    if (info && info->rank == 2 && info->dims) {
      const double values = static_cast<double>(info->dims[0]) * static_cast<double>(info->dims[1]);
      const double storable =
          static_cast<double>(fileBytes) * (info->compression == MAT_COMPRESSION_ZLIB ? 1032.0 : 1.0);
      if (values > storable)
        throw malformed(file, 0,
                        std::string("variable '") + name + "' claims " + std::to_string(info->dims[0]) + " x " +
                            std::to_string(info->dims[1]) + " values, more than a file of " +
                            std::to_string(fileBytes) + " bytes can hold");
      requireWithinMemoryBudget(values * 2 * sizeof(double), file + ": variable '" + name + "'");
    }
  }
  lastMatioMessage.clear();
  std::unique_ptr<matvar_t, VarFreer> var(Mat_VarRead(mat, name));
  if (!var)
    throw malformed(file, 0,
                    std::string("variable '") + name + "' is missing or unreadable" +
                        (lastMatioMessage.empty() ? "" : " (" + lastMatioMessage + ")"));
  const std::string what = std::string("variable '") + name + "'";
  if (var->rank != 2)
    throw malformed(file, 0, what + " must be a 2-D matrix, has " + std::to_string(var->rank) + " dimensions");
  if (var->isComplex) throw malformed(file, 0, what + " must be real, is complex");
  const auto rows = static_cast<Eigen::Index>(var->dims[0]), cols = static_cast<Eigen::Index>(var->dims[1]);
  if (rows * cols > 0 && var->data == nullptr) throw malformed(file, 0, what + " has no data");
  Eigen::MatrixXd matrix(rows, cols);
  if (var->class_type == MAT_C_DOUBLE && var->data_type == MAT_T_DOUBLE) {
    matrix = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(var->data), rows, cols);
  } else if (var->class_type == MAT_C_SINGLE && var->data_type == MAT_T_SINGLE) {
    matrix = Eigen::Map<const Eigen::MatrixXf>(static_cast<const float*>(var->data), rows, cols).cast<double>();
  } else {
    throw malformed(file, 0, what + " must be a double or single matrix");
  }
  for (Eigen::Index c = 0; c < cols; ++c)
    for (Eigen::Index r = 0; r < rows; ++r)
      if (!std::isfinite(matrix(r, c)))
        throw malformed(file, 0,
                        what + " row " + std::to_string(r + 1) + " column " + std::to_string(c + 1) +
                            " is not finite (NaN or infinity)");
  return matrix;
}

bool hasVariable(mat_t* mat, const char* name) {
  std::unique_ptr<matvar_t, VarFreer> info(Mat_VarReadInfo(mat, name));
  return info != nullptr;
}

// theta, phi of a direction given as N x 2 angles or N x 3 unit vectors (row r).
std::pair<double, double> directionAngles(const Eigen::MatrixXd& m, Eigen::Index r, const std::string& file,
                                          const char* name) {
  if (m.cols() == 2) return {m(r, 0), m(r, 1)};
  const Vec3 v = m.row(r).transpose();
  const double length = v.norm();
  if (!(std::abs(length - 1.0) <= 1e-3))
    throw malformed(file, 0,
                    std::string("variable '") + name + "' row " + std::to_string(r + 1) +
                        " is not a unit vector (length " + measured::formatShortest(length) + ")");
  const Vec3 u = v / length;
  return {std::acos(std::clamp(u.z(), -1.0, 1.0)), std::atan2(u.y(), u.x())};
}

// Reads the file once and refuses what libmatio would read wrongly, returning the file's size:
// - without a v5/v7.3 header libmatio falls back to MATLAB v4 and allocates whatever the first
//   bytes claim (a 21-byte file asked for 1.1 GB), so the 128-byte header (text from "MATLAB ",
//   endian indicator "IM" or "MI" in bytes 126-127) is required;
// - libmatio reads a cut-off variable as if the missing bytes were zeros, and allocates what nested
//   tags and dimensions claim before it notices the file cannot hold them, so a level-5 file's
//   data elements are all walked and checked (requireSaneMatStructure); v7.3 files are HDF5, which
//   checks itself.
std::uintmax_t requireCompleteMatFile(const std::filesystem::path& path) {
  const std::string bytes = readTextFile(path, "MATLAB table");
  if (bytes.size() < 128 || bytes.compare(0, 7, "MATLAB ") != 0 ||
      (bytes.compare(126, 2, "IM") != 0 && bytes.compare(126, 2, "MI") != 0))
    throw malformed(path.string(), 0,
                    "not a MATLAB .mat file (v5 or v7.3 need a 128-byte header starting with \"MATLAB \")");
  if (bytes.compare(0, 10, "MATLAB 5.0") == 0) measured::requireSaneMatStructure(bytes, path.string());
  return bytes.size();
}

// An open .mat file and what its variables are read with.
struct MatFile {
  std::unique_ptr<mat_t, MatCloser> mat;
  std::string file;
  std::uintmax_t bytes = 0;  // the file's size, which bounds what its variables may claim

  Eigen::MatrixXd read(const char* name) const { return readMatrix(mat.get(), name, file, bytes); }
  bool has(const char* name) const { return hasVariable(mat.get(), name); }
};

MatFile openMatFile(const std::filesystem::path& path) {
  MatFile mat;
  mat.file = path.string();
  silenceMatio();
  mat.bytes = requireCompleteMatFile(path);
  lastMatioMessage.clear();
  mat.mat.reset(Mat_Open(mat.file.c_str(), MAT_ACC_RDONLY));
  if (!mat.mat)
    throw malformed(mat.file, 0,
                    "not a MATLAB .mat file libmatio can read" +
                        (lastMatioMessage.empty() ? std::string() : " (" + lastMatioMessage + ")"));
  return mat;
}

// The sample directions: 'dir_in' N x 4 (all four angles, `out` empty) or 'dir_in' and 'dir_out',
// each N x 2 [theta phi] or N x 3 unit vectors.
struct MatDirections {
  Eigen::MatrixXd in, out;
  bool combined = false;
};

MatDirections readDirections(const MatFile& mat) {
  const std::string& file = mat.file;
  MatDirections d;
  d.in = mat.read("dir_in");
  d.combined = d.in.cols() == 4;
  if (d.combined) {
    if (mat.has("dir_out"))
      throw malformed(file, 0, "variable 'dir_in' is N x 4 (all four angles), so 'dir_out' must be absent");
    return d;
  }
  if (d.in.cols() != 2 && d.in.cols() != 3)
    throw malformed(file, 0,
                    "variable 'dir_in' must be N x 2 [theta phi], N x 3 unit vectors or N x 4 "
                    "[theta_i phi_i theta_s phi_s], is " +
                        std::to_string(d.in.rows()) + " x " + std::to_string(d.in.cols()));
  d.out = mat.read("dir_out");
  if (d.out.cols() != 2 && d.out.cols() != 3)
    throw malformed(file, 0,
                    "variable 'dir_out' must be N x 2 [theta phi] or N x 3 unit vectors, is " +
                        std::to_string(d.out.rows()) + " x " + std::to_string(d.out.cols()));
  if (d.out.rows() != d.in.rows())
    throw malformed(
        file, 0,
        "'dir_in' has " + std::to_string(d.in.rows()) + " rows but 'dir_out' has " + std::to_string(d.out.rows()));
  return d;
}

// 'fr': one row per direction, one column per channel.
Eigen::MatrixXd readValues(const MatFile& mat, Eigen::Index n) {
  const std::string& file = mat.file;
  Eigen::MatrixXd fr = mat.read("fr");
  if (n == 0) throw malformed(file, 0, "no samples ('dir_in' has 0 rows)");
  if (fr.rows() != n)
    throw malformed(file, 0,
                    "'fr' has " + std::to_string(fr.rows()) + " rows for " + std::to_string(n) +
                        " directions (expected N x channels)");
  if (fr.cols() < 1) throw malformed(file, 0, "'fr' has no channels");
  return fr;
}

// The channels of 'fr' (`channels` columns): spectral with a 'wavelength' variable, else RGB or one channel.
void readChannels(const MatFile& mat, Eigen::Index channels, MeasuredTable& table) {
  const std::string& file = mat.file;
  if (mat.has("wavelength")) {
    const Eigen::MatrixXd w = mat.read("wavelength");
    if (std::min(w.rows(), w.cols()) != 1 || w.size() != channels)
      throw malformed(file, 0,
                      "variable 'wavelength' must be a vector of " + std::to_string(channels) +
                          " wavelengths (one per column of 'fr'), is " + std::to_string(w.rows()) + " x " +
                          std::to_string(w.cols()));
    table.kind = ChannelKind::Spectral;
    for (Eigen::Index c = 0; c < w.size(); ++c) {
      const double nm = w(c);
      if (!(nm > 0.0) || (c > 0 && !(nm > table.wavelengthsNm.back())))
        throw malformed(file, 0, "variable 'wavelength' must be positive and strictly increasing (nm)");
      table.wavelengthsNm.push_back(nm);
      table.channelNames.push_back(measured::wavelengthChannelName(nm));
    }
  } else if (channels == 3) {
    table.kind = ChannelKind::Trichromatic;
    table.channelNames = {"R", "G", "B"};
    table.notes.push_back("RGB channels are taken as stored; the file does not say which primaries they use");
  } else if (channels == 1) {
    table.kind = ChannelKind::Monochrome;
    table.channelNames = {"fr"};
  } else {
    throw malformed(file, 0,
                    "'fr' has " + std::to_string(channels) +
                        " channels but there is no 'wavelength' variable (without it 'fr' must have 1 or 3)");
  }
}

// Every sample's four angles, checked.
void readSampleAngles(const MatDirections& d, const std::string& file, MeasuredTable& table) {
  const Eigen::Index n = d.in.rows();
  table.angles.resize(static_cast<std::size_t>(n));
  for (Eigen::Index r = 0; r < n; ++r) {
    SampleAngles& a = table.angles[static_cast<std::size_t>(r)];
    if (d.combined) {
      a = {d.in(r, 0), d.in(r, 1), d.in(r, 2), d.in(r, 3)};
    } else {
      std::tie(a.thetaIn, a.phiIn) = directionAngles(d.in, r, file, "dir_in");
      std::tie(a.thetaOut, a.phiOut) = directionAngles(d.out, r, file, "dir_out");
    }
    measured::checkAngles(a, file, 0, "sample " + std::to_string(r + 1) + ": ");
  }
}

}  // namespace

MeasuredTable readMat(const std::filesystem::path& path) {
  const MatFile mat = openMatFile(path);
  const MatDirections directions = readDirections(mat);
  const Eigen::MatrixXd fr = readValues(mat, directions.in.rows());
  MeasuredTable table;
  table.sourceFile = mat.file;
  table.format = TableFormat::Mat;
  readChannels(mat, fr.cols(), table);
  readSampleAngles(directions, mat.file, table);
  table.values = fr;
  measured::noteNegativeValues(table);
  return table;
}

}  // namespace brdfbake
