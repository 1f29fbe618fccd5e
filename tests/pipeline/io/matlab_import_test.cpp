// MATLAB v7.3 import (pipeline/io/matlab_import.h). The files are written with the plain HDF5 C
// API the way MATLAB lays them out (512-byte user block with MATLAB's text header, variables as
// datasets with a MATLAB_class attribute, column-major data: an N x A matrix as HDF5 [A, N]), and
// every expected value is computed from the sample and axis index, independently of the importer.
#include "pipeline/io/matlab_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "pipeline/io/recording_import.h"
#include "tests/pipeline/io/import_test_support.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::io {
namespace {

using fogpipe::testing::Layout;
using fogpipe::testing::RawFile;
using fogpipe::testing::Refused;
using fogpipe::testing::TempDir;

/// Element (k, a) of the N x A MATLAB matrix the tests store: sample k of axis a.
double Element(long long k, int a) { return 0.5 * static_cast<double>(k) - 1000.0 * a; }

/// The HDF5 buffer of an N x A MATLAB matrix: column-major, i.e. row-major [A, N].
std::vector<double> ColumnMajor(long long n, int axes) {
  std::vector<double> values;
  for (int a = 0; a < axes; ++a) {
    for (long long k = 0; k < n; ++k) values.push_back(Element(k, a));
  }
  return values;
}

/// Writes MATLAB's text header into the user block, as MATLAB does.
void WriteMatlabHeader(const std::string& path) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  const std::string header =
      "MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Sun Mar  1 "
      "08:00:00 2026 HDF5 schema 1.00 .";
  file.write(header.data(), static_cast<std::streamsize>(header.size()));
}

/// A MATLAB variable: dataset + MATLAB_class.
void Variable(RawFile* file, const std::string& name, const std::vector<hsize_t>& hdf5_dims,
              const std::vector<double>& values, const std::string& matlab_class = "double",
              hid_t type = H5T_IEEE_F64LE) {
  Layout layout;
  layout.file_type = type;
  file->Dataset(name, hdf5_dims, values, layout);
  file->StringAttribute(name, "MATLAB_class", matlab_class);
}

MatlabImportOptions Options(const std::string& variable) {
  MatlabImportOptions options;
  options.variable = variable;
  options.metadata.rate_units = "deg/s";
  options.metadata.sample_rate_hz = 100.0;
  return options;
}

TEST(MatlabImport, AColumnMajorMatrixIsTransposedToSamplesByAxes) {
  TempDir dir;
  const std::string path = dir.File("rec.mat");
  {
    RawFile file(path, 512);
    Variable(&file, "/rate", {3, 1000}, ColumnMajor(1000, 3));  // MATLAB: 1000 x 3
    file.Close();
  }
  WriteMatlabHeader(path);
  std::string error;
  EXPECT_EQ(DetectImportSourceKind(path, &error), ImportSourceKind::kHdf5) << error;
  const ImportResult r = ImportMatlab(path, Options("rate"));
  ASSERT_TRUE(r.ok()) << r.error;
  const Eigen::MatrixXd& rate = r.recording.data.rate_in_output_unit;
  ASSERT_EQ(rate.rows(), 1000);
  ASSERT_EQ(rate.cols(), 3);
  for (long long k = 0; k < 1000; k += 37) {
    for (int a = 0; a < 3; ++a) EXPECT_EQ(rate(k, a), Element(k, a)) << k << "," << a;
  }
  EXPECT_EQ(r.recording.provenance["source"]["format"], "matlab-v7.3");
  EXPECT_EQ(r.recording.provenance["found"]["matlab_class"], "double");
  EXPECT_EQ(r.recording.provenance["found"]["read_column_major"], true);
}

TEST(MatlabImport, ADatasetWithoutMatlabClassIsTakenAsItsDimsSay) {
  TempDir dir;
  const std::string path = dir.File("plain.h5");
  std::vector<double> row_major;
  for (long long k = 0; k < 200; ++k) {
    for (int a = 0; a < 2; ++a) row_major.push_back(Element(k, a));
  }
  {
    RawFile file(path);
    file.Dataset("/gyro/rate", {200, 2}, row_major);
  }
  const ImportResult r = ImportMatlab(path, Options("/gyro/rate"));
  ASSERT_TRUE(r.ok()) << r.error;
  const Eigen::MatrixXd& rate = r.recording.data.rate_in_output_unit;
  ASSERT_EQ(rate.rows(), 200);
  ASSERT_EQ(rate.cols(), 2);
  EXPECT_EQ(rate(199, 1), Element(199, 1));
  EXPECT_EQ(rate(3, 0), Element(3, 0));
  EXPECT_EQ(r.recording.provenance["source"]["format"], "hdf5");
}

TEST(MatlabImport, MoreAxesThanSamplesIsRefusedAsATransposedMatrix) {
  TempDir dir;
  const std::string path = dir.File("wide.mat");
  {
    RawFile file(path, 512);
    // HDF5 [1000, 3] with MATLAB_class is a 3 x 1000 MATLAB matrix: 1000 axes of 3 samples.
    Variable(&file, "/rate", {1000, 3}, ColumnMajor(1000, 3));
  }
  const ImportResult r = ImportMatlab(path, Options("rate"));
  EXPECT_TRUE(Refused(r, "wide.mat: variable 'rate' is a 3 x 1000 matrix"));
  EXPECT_TRUE(Refused(r, "a transposed matrix?"));
}

TEST(MatlabImport, AVectorIsOneAxisInEitherOrientation) {
  TempDir dir;
  const std::string path = dir.File("vec.mat");
  std::vector<double> values;
  for (long long k = 0; k < 300; ++k) values.push_back(Element(k, 0));
  {
    RawFile file(path, 512);
    Variable(&file, "/column", {1, 300}, values);  // MATLAB 300 x 1
    Variable(&file, "/row", {300, 1}, values);     // MATLAB 1 x 300
  }
  for (const char* name : {"column", "row"}) {
    const ImportResult r = ImportMatlab(path, Options(name));
    ASSERT_TRUE(r.ok()) << name << ": " << r.error;
    const Eigen::MatrixXd& rate = r.recording.data.rate_in_output_unit;
    ASSERT_EQ(rate.rows(), 300) << name;
    ASSERT_EQ(rate.cols(), 1) << name;
    EXPECT_EQ(rate(0, 0), Element(0, 0));
    EXPECT_EQ(rate(299, 0), Element(299, 0));
  }
}

TEST(MatlabImport, SampleRateAndAuxFromVariablesAndStructFields) {
  TempDir dir;
  const std::string path = dir.File("full.mat");
  std::vector<double> temperature;
  for (long long k = 0; k < 500; ++k) temperature.push_back(20.0 + 0.01 * static_cast<double>(k));
  {
    RawFile file(path, 512);
    file.Group("/gyro");
    file.StringAttribute("/gyro", "MATLAB_class", "struct");
    Variable(&file, "/gyro/rate", {2, 500}, ColumnMajor(500, 2));
    Variable(&file, "/gyro/fs", {1, 1}, {250.0});
    Variable(&file, "/T", {1, 500}, temperature);
  }
  MatlabImportOptions options = Options("gyro.rate");
  options.metadata.sample_rate_hz = 0.0;
  options.sample_rate_variable = "gyro.fs";
  options.metadata.aux = {{"temperature", "T", "degC"}};
  const ImportResult r = ImportMatlab(path, options);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.recording.data.sample_rate_hz, 250.0);
  const AuxChannel& t = r.recording.data.aux.at("temperature");
  EXPECT_EQ(t.units, "degC");
  ASSERT_EQ(t.samples.size(), 500);
  EXPECT_EQ(t.samples[123], temperature[123]);

  // A struct named as the rate is refused, naming its fields.
  const ImportResult group = ImportMatlab(path, Options("gyro"));
  EXPECT_TRUE(Refused(group, "its fields: 'fs', 'rate'"));
}

TEST(MatlabImport, IntegerCountsAreMultipliedByTheScaleFactor) {
  TempDir dir;
  const std::string path = dir.File("counts.mat");
  std::vector<double> counts;
  for (long long k = 0; k < 100; ++k) counts.push_back(static_cast<double>((k * 37) % 201 - 100));
  {
    RawFile file(path, 512);
    Variable(&file, "/counts", {1, 100}, counts, "int16", H5T_STD_I16LE);
  }
  MatlabImportOptions options = Options("counts");
  options.metadata.scale_factor = 0.25;
  const ImportResult r = ImportMatlab(path, options);
  ASSERT_TRUE(r.ok()) << r.error;
  const Eigen::MatrixXd& rate = r.recording.data.rate_in_output_unit;
  for (long long k = 0; k < 100; ++k) EXPECT_EQ(rate(k, 0), counts[k] * 0.25) << k;
}

TEST(MatlabImport, AnOlderMatFileIsRefusedWithAdvice) {
  TempDir dir;
  const std::string path = dir.File("v7.mat");
  {
    std::ofstream file(path, std::ios::binary);
    std::string header = "MATLAB 5.0 MAT-file, Platform: PCWIN64, Created on: Sun Mar 1 2026";
    header.resize(128, ' ');
    file << header << std::string(256, '\0');
  }
  std::string error;
  EXPECT_EQ(DetectImportSourceKind(path, &error), ImportSourceKind::kOldMatFile);
  const ImportResult r = ImportMatlab(path, Options("rate"));
  EXPECT_TRUE(Refused(r, "v7.mat:"));
  EXPECT_TRUE(Refused(r, "-v7.3"));
  EXPECT_TRUE(Refused(r, "CSV"));
}

TEST(MatlabImport, ATextFileIsDetectedAsText) {
  TempDir dir;
  const std::string path = dir.File("a.csv");
  std::ofstream(path) << "t,x\n0,1\n";
  std::string error;
  EXPECT_EQ(DetectImportSourceKind(path, &error), ImportSourceKind::kText);
}

TEST(MatlabImport, MissingOrWrongVariablesAreNamed) {
  TempDir dir;
  const std::string path = dir.File("vars.mat");
  {
    RawFile file(path, 512);
    Variable(&file, "/rate", {1, 100}, ColumnMajor(100, 1));
    Variable(&file, "/T", {1, 99}, ColumnMajor(99, 1));
    Variable(&file, "/fs", {1, 2}, {1.0, 2.0});
    Variable(&file, "/name", {1, 3}, {65, 66, 67}, "char", H5T_STD_U16LE);
  }
  ImportResult r = ImportMatlab(path, Options(""));
  EXPECT_TRUE(Refused(r, "give --variable (variables: 'T', 'fs', 'name', 'rate')"));
  r = ImportMatlab(path, Options("gyro"));
  EXPECT_TRUE(Refused(r, "variable 'gyro' is not in the file"));
  r = ImportMatlab(path, Options("name"));
  EXPECT_TRUE(Refused(r, "is a MATLAB 'char' array"));
  MatlabImportOptions options = Options("rate");
  options.metadata.aux = {{"temperature", "T", "degC"}};
  r = ImportMatlab(path, options);
  EXPECT_TRUE(Refused(r, "aux 'temperature': variable 'T' is a 99 x 1 array"));
  options = Options("rate");
  options.metadata.sample_rate_hz = 0.0;
  options.sample_rate_variable = "fs";
  r = ImportMatlab(path, options);
  EXPECT_TRUE(Refused(r, "the sample rate is one number"));
}

TEST(MatlabImport, AnImportedMatrixIsWrittenBitForBit) {
  TempDir dir;
  const std::string path = dir.File("exact.mat");
  std::vector<double> values = ColumnMajor(400, 3);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::sin(0.1 * i) / 3.0;
  {
    RawFile file(path, 512);
    Variable(&file, "/rate", {3, 400}, values);
  }
  const ImportResult r = ImportMatlab(path, Options("rate"));
  ASSERT_TRUE(r.ok()) << r.error;
  const std::string out = dir.File("exact.h5");
  const ImportWriteResult w = WriteImportedRecording(out, r.recording);
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.info.samples, 400);
  EXPECT_EQ(w.info.axis_count, 3);
  EXPECT_EQ(w.info.rate_units, "deg/s");
  // Read back with the C API: [400, 3] row-major, element (k, a) = values[a * 400 + k].
  hid_t file = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  hid_t dataset = H5Dopen2(file, "/rate", H5P_DEFAULT);
  std::vector<double> stored(1200);
  ASSERT_GE(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, stored.data()), 0);
  H5Dclose(dataset);
  H5Fclose(file);
  for (long long k = 0; k < 400; ++k) {
    for (int a = 0; a < 3; ++a) ASSERT_EQ(stored[3 * k + a], values[a * 400 + k]) << k << "," << a;
  }
}

}  // namespace
}  // namespace fogpipe::io
