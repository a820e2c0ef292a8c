#pragma once
/// @file
/// Reading and writing measured BRDF tables (docs/measured_tables.md). Every reader throws
/// Error(Io) when the file cannot be read and Error(InvalidInput) for a malformed file, with a
/// message "<file>:<line>: ..." naming the line where the file has lines. No NaN or infinity
/// ever leaves a reader: a non-finite field is an error.

#include <brdfbake/measured/measured_table.hpp>

#include <filesystem>

namespace brdfbake {

/// The format of a file by its content, not its name:
/// - Mat: a MATLAB header ("MATLAB 5.0 MAT-file" or "MATLAB 7.3 MAT-file") in the first bytes;
/// - Merl: at least 12 bytes whose first three little-endian int32 are 90, 90, 180;
/// - Astm: the first non-blank line is `KEY value` with KEY in upper case (readAstm then insists
///   on the `VARS` line, so a header without it is reported as such, with its line);
/// - Pbrt: after blank and `#` comment lines, the first token is a positive integer (the number
///   of wavelengths).
/// Throws Error(InvalidInput) naming the file if none fits, Error(Io) if it cannot be read.
TableFormat detectTableFormat(const std::filesystem::path& path);

/// Cornell ASTM E1392 text: LF or CRLF; `KEY value` header lines (blank lines allowed) ending
/// with `VARS theta_i,phi_i,theta_s,phi_s,<channels>`; then one comma-separated row per sample.
/// Channels named `<number>nm` are spectral, `R,G,B` RGB, a single other name monochrome.
/// `NUM_POINTS`, when present, must equal the number of rows (without it a note says so).
MeasuredTable readAstm(const std::filesystem::path& path);

/// pbrt-v2 `.brdf`: `#` comments anywhere; the number of wavelengths N; the N wavelengths (nm,
/// over one or more lines); then one sample per line, whitespace-separated:
/// theta_i phi_i theta_s phi_s v1 .. vN.
MeasuredTable readPbrt(const std::filesystem::path& path);

/// MATLAB .mat (v5, or v7.3 where libmatio has HDF5) with Cornell's variables, real double or
/// single matrices, N samples:
/// - `dir_in`, `dir_out`: N x 2 [theta phi] in radians, or N x 3 unit vectors in the local frame;
///   or `dir_in` alone as N x 4 [theta_i phi_i theta_s phi_s];
/// - `fr`: N x C BRDF values (1/sr);
/// - `wavelength` (optional): C wavelengths in nm (vector) -> spectral; without it C = 3 is RGB
///   and C = 1 monochrome.
/// Errors name the file and the variable (row and column for bad numbers).
MeasuredTable readMat(const std::filesystem::path& path);

/// MERL `.binary`: three little-endian int32 dims 90 90 180, then 3 * 90 * 90 * 180 doubles
/// (channel-major R, G, B). The size is checked before anything is read: the file must be
/// exactly 12 + 3 * 8 * 90 * 90 * 180 = 34 992 012 bytes.
MerlTable readMerl(const std::filesystem::path& path);

/// Reads a tabulated file (ASTM, pbrt or MAT) in the given format, or the detected one for
/// Auto. Throws Error(InvalidArgument) for Merl (dense: use readMerl) and Error(InvalidInput)
/// when Auto detects MERL.
MeasuredTable readMeasuredTable(const std::filesystem::path& path, TableFormat format = TableFormat::Auto);

/// Writes `table` as ASTM E1392 text (LF line ends): its ASTM header lines (other than
/// NUM_POINTS and VARS), NUM_POINTS, VARS, and one row per sample with the shortest decimal
/// form that reads back to the same double. Throws Error(InvalidInput) if the table does not
/// validate, Error(Io) if the file cannot be written.
void writeAstm(const std::filesystem::path& path, const MeasuredTable& table);

}  // namespace brdfbake
