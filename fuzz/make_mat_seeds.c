/* Writes the small .mat seeds of fuzz/corpus/mat/ with libmatio (Cornell's variable layout, 3
 * samples). Build and run from fuzz/: cc make_mat_seeds.c -lmatio -o /tmp/mms && /tmp/mms corpus/mat */
#include <matio.h>
#include <stdio.h>
#include <string.h>

static enum matio_compression compression = MAT_COMPRESSION_NONE;

static void put(mat_t* mat, const char* name, size_t rows, size_t cols, double* data, int single) {
  size_t dims[2] = {rows, cols};
  float f[64];
  matvar_t* var;
  if (single) {
    for (size_t i = 0; i < rows * cols; ++i) f[i] = (float)data[i];
    var = Mat_VarCreate(name, MAT_C_SINGLE, MAT_T_SINGLE, 2, dims, f, 0);
  } else {
    var = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data, 0);
  }
  Mat_VarWrite(mat, var, compression);
  Mat_VarFree(var);
}

int main(int argc, char** argv) {
  const char* dir = argc > 1 ? argv[1] : ".";
  char path[512];
  /* column-major 3 x 2: theta column then phi column */
  double in2[] = {0.17, 0.35, 0.52, 0, 0, 0};
  double out2[] = {0.26, 0.26, 0.26, 3.14159, -1.5708, 0};
  double in4[] = {0.17, 0.35, 0.52, 0, 0, 0, 0.26, 0.26, 0.26, 3.14159, -1.5708, 0};
  double out3[] = {0.0, 0.1, 0.2, 0.0, 0.0, 0.0, 1.0, 0.99499, 0.97980};
  double fr3[] = {1, 2, 3, 1.01, 2.01, 3.01, 1.02, 2.02, 3.02};
  double fr4[] = {1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3};
  double wl[] = {400, 500, 600, 700};
  mat_t* mat;

  snprintf(path, sizeof path, "%s/angles_rgb.mat", dir);
  mat = Mat_CreateVer(path, NULL, MAT_FT_MAT5);
  put(mat, "dir_in", 3, 2, in2, 0);
  put(mat, "dir_out", 3, 2, out2, 0);
  put(mat, "fr", 3, 3, fr3, 0);
  Mat_Close(mat);

  snprintf(path, sizeof path, "%s/spectral_single.mat", dir);
  mat = Mat_CreateVer(path, NULL, MAT_FT_MAT5);
  put(mat, "dir_in", 3, 4, in4, 1);
  put(mat, "fr", 3, 4, fr4, 1);
  put(mat, "wavelength", 1, 4, wl, 1);
  Mat_Close(mat);

  snprintf(path, sizeof path, "%s/vectors_mono.mat", dir);
  mat = Mat_CreateVer(path, NULL, MAT_FT_MAT5);
  put(mat, "dir_in", 3, 3, out3, 0);
  put(mat, "dir_out", 3, 3, out3, 0);
  put(mat, "fr", 3, 1, fr3, 0);
  Mat_Close(mat);

  compression = MAT_COMPRESSION_ZLIB;
  snprintf(path, sizeof path, "%s/angles_rgb_zlib.mat", dir);
  mat = Mat_CreateVer(path, NULL, MAT_FT_MAT5);
  put(mat, "dir_in", 3, 2, in2, 0);
  put(mat, "dir_out", 3, 2, out2, 0);
  put(mat, "fr", 3, 3, fr3, 0);
  Mat_Close(mat);

  /* Nested cells and a struct before the table, so the fuzzer starts from the structures the
   * checks of measured/mat_structure.cpp walk. */
  compression = MAT_COMPRESSION_NONE;
  snprintf(path, sizeof path, "%s/cells_struct.mat", dir);
  mat = Mat_CreateVer(path, NULL, MAT_FT_MAT5);
  {
    size_t one[2] = {1, 1}, two[2] = {2, 1};
    double value = 1.5;
    const char* fields[2] = {"a", "b"};
    matvar_t* inner[2] = {Mat_VarCreate(NULL, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &value, 0),
                          Mat_VarCreate(NULL, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &value, 0)};
    matvar_t* nested[2] = {Mat_VarCreate(NULL, MAT_C_CELL, MAT_T_CELL, 2, two, inner, 0),
                           Mat_VarCreate(NULL, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &value, 0)};
    matvar_t* cells = Mat_VarCreate("notes", MAT_C_CELL, MAT_T_CELL, 2, two, nested, 0);
    matvar_t* info = Mat_VarCreateStruct("info", 2, one, fields, 2);
    Mat_VarSetStructFieldByName(info, "a", 0, Mat_VarCreate(NULL, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &value, 0));
    Mat_VarWrite(mat, cells, MAT_COMPRESSION_NONE);
    Mat_VarWrite(mat, info, MAT_COMPRESSION_ZLIB);
    Mat_VarFree(cells);
    Mat_VarFree(info);
  }
  put(mat, "dir_in", 3, 2, in2, 0);
  put(mat, "dir_out", 3, 2, out2, 0);
  put(mat, "fr", 3, 3, fr3, 0);
  Mat_Close(mat);
  return 0;
}
