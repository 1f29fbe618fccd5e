// Text import (pipeline/io/text_import.h): every expected value below is written literally in the
// test's own text file, and written recordings are read back with the HDF5 C++ API directly.
#include "pipeline/io/text_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "pipeline/io/recording_import.h"
#include "tests/pipeline/cli/simulate_test_support.h"
#include "tests/pipeline/io/import_test_support.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::io {
namespace {

using fogpipe::testing::EntriesIn;
using fogpipe::testing::RateIs;
using fogpipe::testing::Refused;
using fogpipe::testing::TempDir;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string WriteText(const TempDir& dir, const std::string& name, const std::string& text) {
  return fogpipe::testing::WriteTextFile(dir.File(name), text);
}

TextImportOptions Options(const std::string& units = "deg/h") {
  TextImportOptions options;
  options.metadata.rate_units = units;
  options.metadata.sample_rate_hz = 10.0;
  return options;
}

/// Options for a file whose sample rate comes from its time column `column`.
TextImportOptions TimedOptions(const std::string& column, const std::string& time_units = "s") {
  TextImportOptions options = Options();
  options.metadata.sample_rate_hz = 0.0;
  options.time_column = column;
  options.time_units = time_units;
  return options;
}

const nlohmann::json& Found(const ImportResult& result) {
  return result.recording.provenance["found"];
}

TEST(TextImport, DetectsCommaSemicolonTabAndBlankDelimiters) {
  TempDir dir;
  const struct {
    const char* separator;
    const char* name;
  } cases[] = {{",", ","}, {";", ";"}, {"\t", "tab"}, {"   ", "space"}};
  for (const auto& c : cases) {
    const std::string sep = c.separator;
    const std::string path =
        WriteText(dir, std::string("d_") + c.name + ".txt",
                  "1.5" + sep + "-2" + sep + "3e-3\n" + "4" + sep + "5.25" + sep + "-6\n");
    TextImportOptions options = Options();
    options.rate_columns = {"0", "1", "2"};
    const ImportResult r = ImportText(path, options);
    EXPECT_TRUE(RateIs(r, {{1.5, -2.0, 3e-3}, {4.0, 5.25, -6.0}})) << c.name;
    EXPECT_EQ(Found(r)["delimiter"], c.name);
  }
}

TEST(TextImport, GivenDelimiterAndDecimalCommaAreUsed) {
  TempDir dir;
  const std::string path = WriteText(dir, "eu.csv", "x;y\n1,5;-2,25\n3;4,125\n");
  TextImportOptions options = Options();
  options.delimiter = ";";
  options.decimal_comma = true;
  options.rate_columns = {"x", "y"};
  EXPECT_TRUE(RateIs(ImportText(path, options), {{1.5, -2.25}, {3.0, 4.125}}));
}

TEST(TextImport, HeaderNamesSelectAndOrderColumnsAndNameTheAxes) {
  TempDir dir;
  const std::string path = WriteText(dir, "h.csv",
                                     "\"time\", gx, gy, gz, temp\n"
                                     "0, 1, 2, 3, 25.5\n"
                                     "0.1, 4, 5, 6, 25.75\n");
  TextImportOptions options = Options();
  options.rate_columns = {"gz", "gx"};
  options.metadata.aux = {{"temperature", "temp", "degC"}};
  const ImportResult r = ImportText(path, options);
  ASSERT_TRUE(RateIs(r, {{3.0, 1.0}, {6.0, 4.0}}));
  EXPECT_EQ(r.recording.data.axes, (std::vector<std::string>{"gz", "gx"}));
  const AuxChannel& t = r.recording.data.aux.at("temperature");
  EXPECT_EQ(t.units, "degC");
  EXPECT_EQ(t.samples[0], 25.5);
  EXPECT_EQ(t.samples[1], 25.75);
}

TEST(TextImport, ColumnsByIndexWithoutHeaderAndExplicitAxisNames) {
  TempDir dir;
  const std::string path = WriteText(dir, "n.txt", "10 20 30\n11 21 31\n");
  TextImportOptions options = Options();
  options.rate_columns = {"2", "0"};
  options.metadata.axes = {"up", "north"};
  const ImportResult r = ImportText(path, options);
  EXPECT_TRUE(RateIs(r, {{30.0, 10.0}, {31.0, 11.0}}));
  EXPECT_EQ(r.recording.data.axes, (std::vector<std::string>{"up", "north"}));
  EXPECT_TRUE(Found(r)["header_line"].is_null());
}

TEST(TextImport, AnAllNumericFirstLineIsDataAndHeaderNoKeepsAWordyFirstLineOut) {
  TempDir dir;
  TextImportOptions options = Options();
  options.rate_columns = {"0", "1"};
  EXPECT_TRUE(
      RateIs(ImportText(WriteText(dir, "a.csv", "1,2\n3,4\n"), options), {{1.0, 2.0}, {3.0, 4.0}}));
  // header "no": a first line that is not numbers is a bad cell, not a header.
  options.header = "no";
  EXPECT_TRUE(Refused(ImportText(WriteText(dir, "b.csv", "x,y\n3,4\n"), options),
                      "line 1, column 0 (0-based): 'x' is not a number"));
}

TEST(TextImport, SkipRowsCommentsBlankLinesCrLfAndByteOrderMark) {
  TempDir dir;
  const std::string path = WriteText(dir, "pre.csv",
                                     "\xEF\xBB\xBFGyro logger v2, unit 7\r\n"
                                     "recorded 2026-03-01\r\n"
                                     "t,rate\r\n"
                                     "# a comment\r\n"
                                     "0,1.25\r\n"
                                     "\r\n"
                                     "0.1,2.5\r\n"
                                     "  # indented comment\r\n"
                                     "0.2,3.75");  // no newline at the end
  TextImportOptions options = TimedOptions("t");
  options.skip_rows = 2;
  const ImportResult r = ImportText(path, options);
  ASSERT_TRUE(RateIs(r, {{1.25}, {2.5}, {3.75}}));
  EXPECT_EQ(Found(r)["header_line"], 3);
  EXPECT_EQ(Found(r)["first_data_line"], 5);
  EXPECT_EQ(Found(r)["last_data_line"], 9);
  // The one column that is not the time column is the rate; the header names the axis.
  EXPECT_EQ(r.recording.data.axes, std::vector<std::string>{"rate"});
  EXPECT_EQ(r.recording.data.sample_rate_hz, 10.0);
}

TEST(TextImport, TimeColumnInSecondsGivesTheSampleRate) {
  TempDir dir;
  std::string text = "t,x\n";
  for (int k = 0; k < 500; ++k) {
    char line[64];
    std::snprintf(line, sizeof line, "%.17g,%d\n", k * 0.01, k % 7);
    text += line;
  }
  const ImportResult r = ImportText(WriteText(dir, "t.csv", text), TimedOptions("t"));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.recording.data.sample_rate_hz, 100.0);
  EXPECT_EQ(r.recording.data.rate_in_output_unit.rows(), 500);
  EXPECT_EQ(r.recording.data.rate_in_output_unit.cols(), 1);
}

TEST(TextImport, TimeColumnInMillisecondsAndEpochNanoseconds) {
  TempDir dir;
  std::string ms = "ms x\n";
  std::string ns = "ns x\n";
  for (int k = 0; k < 200; ++k) {
    ms += std::to_string(1000 + 4 * k) + " " + std::to_string(k % 5) + "\n";
    // 2026-01-01T00:00:00Z in ns plus 5 ms steps: beyond a double's 53 bits.
    ns +=
        std::to_string(1767225600000000000LL + 5000000LL * k) + " " + std::to_string(k % 5) + "\n";
  }
  ImportResult r = ImportText(WriteText(dir, "ms.txt", ms), TimedOptions("ms", "ms"));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.recording.data.sample_rate_hz, 250.0);
  r = ImportText(WriteText(dir, "ns.txt", ns), TimedOptions("ns", "ns"));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.recording.data.sample_rate_hz, 200.0);
}

TEST(TextImport, NonUniformTimeColumnIsRefusedNamingTheFirstBadLine) {
  TempDir dir;
  // Line 1 is the header; rows at lines 2.. have t = 0, 0.01, ...; line 7 jumps by 1.5 steps.
  std::string text = "t,x\n";
  for (int k = 0; k < 50; ++k) {
    const double t = k * 0.01 + (k >= 5 ? 0.005 : 0.0);
    text += std::to_string(t) + "," + std::to_string(k % 3) + "\n";
  }
  const ImportResult r = ImportText(WriteText(dir, "jitter.csv", text), TimedOptions("t"));
  EXPECT_TRUE(Refused(r, "jitter.csv: line 7, column 't' (index 0)"));
  EXPECT_TRUE(Refused(r, "not uniform"));
  EXPECT_TRUE(Refused(r, "no gap of whole steps"));
  EXPECT_TRUE(Refused(r, "1 other irregular step"));
}

TEST(TextImport, GapsInTheTimeColumnAreCountedInTheRefusal) {
  TempDir dir;
  // 100 Hz with samples 10-12 missing (one gap of 3) and 40 missing (one gap of 1).
  std::string text = "t x\n";
  for (int k = 0; k < 60; ++k) {
    if ((k >= 10 && k <= 12) || k == 40) continue;
    text += std::to_string(k * 10) + " " + std::to_string(k % 4) + "\n";
  }
  const ImportResult r = ImportText(WriteText(dir, "gaps.txt", text), TimedOptions("t", "ms"));
  // The first gap: after t = 90 ms (line 11) comes t = 130 ms (line 12).
  EXPECT_TRUE(Refused(r, "line 12,"));
  EXPECT_TRUE(Refused(r, "2 gaps of whole steps (4 missing samples, the longest 3 after line 11)"));
}

TEST(TextImport, TimeColumnMustAgreeWithAGivenSampleRate) {
  TempDir dir;
  const std::string path = WriteText(dir, "agree.csv", "t,x\n0,1\n0.5,2\n1.0,3\n");
  TextImportOptions options = TimedOptions("t");
  options.metadata.sample_rate_hz = 2.0;
  EXPECT_TRUE(ImportText(path, options).ok());
  options.metadata.sample_rate_hz = 10.0;
  EXPECT_TRUE(Refused(ImportText(path, options),
                      "gives a sample rate of 2 Hz, --sample-rate-hz says 10 Hz"));
}

TEST(TextImport, IntegerCountsAreMultipliedByTheScaleFactor) {
  TempDir dir;
  const std::string path = WriteText(dir, "counts.txt", "100 -3\n7 0\n-65536 32767\n");
  TextImportOptions options = Options("deg/s");
  options.rate_columns = {"0", "1"};
  options.metadata.scale_factor = 0.5;
  const ImportResult r = ImportText(path, options);
  EXPECT_TRUE(RateIs(r, {{50.0, -1.5}, {3.5, 0.0}, {-32768.0, 16383.5}}));
  EXPECT_EQ(r.recording.rate_unit, units::RateUnit::kDegPerSecond);
}

TEST(TextImport, EmptyNanAndNaCellsBecomeNaN) {
  TempDir dir;
  const std::string path = WriteText(dir, "nan.csv",
                                     "x,y\n"
                                     "1,\n"
                                     "NaN,2\n"
                                     "nan,3\n"
                                     "-nan,NA\n"
                                     "5,6\n");
  TextImportOptions options = Options();
  options.rate_columns = {"x", "y"};
  const ImportResult r = ImportText(path, options);
  EXPECT_TRUE(RateIs(r, {{1.0, kNaN}, {kNaN, 2.0}, {kNaN, 3.0}, {kNaN, kNaN}, {5.0, 6.0}}));
  EXPECT_EQ(Found(r)["missing_samples"]["x"], 3);
  EXPECT_EQ(Found(r)["missing_samples"]["y"], 2);
}

TEST(TextImport, ANanRunLongerThanTheReaderBridgesIsAWarning) {
  TempDir dir;
  std::string text = "x\n";
  for (int k = 0; k < 100; ++k) {
    text += (k >= 20 && k < 32 ? std::string("nan") : std::to_string(k)) + "\n";
  }
  const ImportResult r = ImportText(WriteText(dir, "gap.csv", text), Options());
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.recording.warnings.size(), 1u);
  const std::string& warning = r.recording.warnings[0];
  EXPECT_NE(warning.find("the longest 12 from sample 20"), std::string::npos) << warning;
  EXPECT_NE(warning.find("--max-nan-gap 12"), std::string::npos) << warning;
}

TEST(TextImport, ABadCellIsNamedByFileLineAndColumn) {
  TempDir dir;
  const std::string path = WriteText(dir, "bad.csv", "t,x,y\n0,1,2\n# note\n0.1,3,4O\n0.2,5,6\n");
  TextImportOptions options = Options();
  options.rate_columns = {"x", "y"};
  EXPECT_EQ(ImportText(path, options).error,
            path + ": line 4, column 'y' (index 2): '4O' is not a number");

  const std::string headless = WriteText(dir, "bad.txt", "1 2\n3 x\n");
  options.rate_columns = {"0", "1"};
  EXPECT_EQ(ImportText(headless, options).error,
            headless + ": line 2, column 1 (0-based): 'x' is not a number");
}

TEST(TextImport, AnInfiniteValueAndAShortRowAreRefusedByLine) {
  TempDir dir;
  TextImportOptions options = Options();
  options.rate_columns = {"a", "b"};
  EXPECT_TRUE(Refused(ImportText(WriteText(dir, "inf.csv", "a,b\n1,2\n3,inf\n"), options),
                      "line 3, column 'b' (index 1): 'inf' is infinite"));
  EXPECT_TRUE(Refused(ImportText(WriteText(dir, "short.csv", "a,b\n1,2\n3\n4,5\n"), options),
                      "line 3: 1 field where the header has 2"));
}

TEST(TextImport, UnknownOrAmbiguousColumnsAreRefusedListingTheColumns) {
  TempDir dir;
  const std::string path = WriteText(dir, "cols.csv", "t,x,y\n0,1,2\n1,3,4\n");
  TextImportOptions options = Options();
  options.rate_columns = {"x", "q"};
  EXPECT_TRUE(
      Refused(ImportText(path, options), "--rate-columns: no column 'q' (columns 't', 'x', 'y'"));
  options.rate_columns = {};
  options.time_column = "t";
  EXPECT_TRUE(Refused(ImportText(path, options), "give --rate-columns"));
}

TEST(TextImport, MissingSampleRateAndUnitsAreErrors) {
  TempDir dir;
  TextImportOptions options = Options();
  options.metadata.sample_rate_hz = 0.0;
  EXPECT_TRUE(
      Refused(ImportText(WriteText(dir, "one.txt", "1\n2\n3\n"), options), "no sample rate"));
  options = Options("");
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("deg/h, deg/s or rad/s"), std::string::npos) << error;
}

TEST(TextImport, AOneAxisFileBecomesAOneDimensionalRecording) {
  TempDir dir;
  std::string text;
  for (int k = 0; k < 200; ++k) text += std::to_string(0.25 * (k % 9) - 1.0) + "\n";
  const ImportResult r = ImportText(WriteText(dir, "one.txt", text), Options("rad/s"));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(r.recording.data.axes.empty());
  const std::string out = dir.File("one.h5");
  const ImportWriteResult w = WriteImportedRecording(out, r.recording);
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.info.samples, 200);
  EXPECT_EQ(w.info.axis_count, 1);

  H5::H5File file(out, H5F_ACC_RDONLY);
  H5::DataSet rate = file.openDataSet("rate");
  EXPECT_EQ(fogpipe::testing::Dims(rate), std::vector<hsize_t>{200});
  EXPECT_EQ(fogpipe::testing::ReadStringAttribute(rate, "units"), "rad/s");
  const Eigen::VectorXd stored = fogpipe::testing::ReadAll(rate);
  for (int k = 0; k < 200; ++k) EXPECT_EQ(stored[k], 0.25 * (k % 9) - 1.0) << k;
  EXPECT_EQ(fogpipe::testing::ReadDoubleAttribute(file, "sample_rate_hz"), 10.0);
}

TEST(TextImport, AThreeAxisFileIsWrittenWithProvenanceAndPassesTheRecordingChecks) {
  TempDir dir;
  std::string text = "x,y,z\n";
  for (int k = 0; k < 100; ++k) {
    text += std::to_string(k) + "," + std::to_string(-k) + "," + std::to_string(k * k) + "\n";
  }
  const std::string source = WriteText(dir, "three.csv", text);
  TextImportOptions options = Options("deg/h");
  options.rate_columns = {"x", "y", "z"};
  options.metadata.instrument = "VG951";
  options.metadata.serial = "S-17";
  options.metadata.start_time_utc = "2026-03-01T08:00:00Z";
  options.metadata.latitude_deg = 48.5;
  const ImportResult r = ImportText(source, options);
  ASSERT_TRUE(r.ok()) << r.error;
  const std::string out = dir.File("three.h5");
  const ImportWriteResult w = WriteImportedRecording(out, r.recording);
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.info.axis_names, (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_EQ(EntriesIn(dir.path()), 2);  // the source and the recording: no temporary file

  H5::H5File file(out, H5F_ACC_RDONLY);
  H5::DataSet rate = file.openDataSet("rate");
  EXPECT_EQ(fogpipe::testing::Dims(rate), (std::vector<hsize_t>{100, 3}));
  EXPECT_EQ(rate.getDataType(), H5::PredType::IEEE_F64LE);
  const Eigen::VectorXd stored = fogpipe::testing::ReadAll(rate);
  for (int k = 0; k < 100; ++k) {
    EXPECT_EQ(stored[3 * k], k);
    EXPECT_EQ(stored[3 * k + 1], -k);
    EXPECT_EQ(stored[3 * k + 2], k * k);
  }
  EXPECT_EQ(fogpipe::testing::ReadStringAttribute(file, "instrument"), "VG951");
  EXPECT_EQ(fogpipe::testing::ReadStringAttribute(file, "serial"), "S-17");
  EXPECT_EQ(fogpipe::testing::ReadDoubleAttribute(file, "latitude_deg"), 48.5);
  const nlohmann::json provenance = nlohmann::json::parse(
      fogpipe::testing::ReadStringAttribute(file, kImportProvenanceAttribute));
  EXPECT_EQ(provenance["source"]["format"], "text");
  EXPECT_EQ(provenance["source"]["size_bytes"], static_cast<long long>(text.size()));
  EXPECT_EQ(provenance["source"]["path"], std::filesystem::absolute(source).string());
  EXPECT_EQ(provenance["options"]["rate_columns"], (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_EQ(provenance["options"]["metadata"]["rate_units"], "deg/h");
}

TEST(TextImport, TheProvenanceHoldsTheSourcesSha256) {
  TempDir dir;
  // printf 'x\n1\n2\n' | sha256sum
  const ImportResult r = ImportText(WriteText(dir, "sha.txt", "x\n1\n2\n"), Options());
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.recording.provenance["source"]["sha256"],
            "aea284871ddeeebac4b57b7a8ee7dad070886e690408ce2409306b9b6487beb1");
}

TEST(TextImport, ALatin1HeaderIsImportedAndWritten) {
  TempDir dir;
  // A Latin-1 degree sign (0xB0, not UTF-8), as Windows tools often write it.
  const std::string name = std::string("Temp ") + '\xB0' + "C";
  std::string rows;  // 64 rows: the fewest samples `run` analyses, which the written file must have
  for (int k = 0; k < 64; ++k) rows += std::to_string(k) + "," + std::to_string(20 + k % 3) + "\n";
  const std::string path = WriteText(dir, "latin1.csv", "rate," + name + "\n" + rows);
  TextImportOptions options = Options();
  options.rate_columns = {"rate"};
  options.metadata.aux = {{"temperature", name, "degC"}};
  const ImportResult r = ImportText(path, options);
  ASSERT_TRUE(r.ok()) << r.error;
  const ImportWriteResult w = WriteImportedRecording(dir.File("latin1.h5"), r.recording);
  EXPECT_TRUE(w.ok()) << w.error;
}

TEST(TextImport, AnOutputTheRecordingChecksRefuseNeverAppears) {
  TempDir dir;
  TextImportOptions options = Options();
  options.metadata.start_time_utc = "yesterday";  // not ISO 8601: the layout refuses it
  const ImportResult r = ImportText(WriteText(dir, "in.txt", "1\n2\n3\n"), options);
  ASSERT_TRUE(r.ok()) << r.error;
  const ImportWriteResult w = WriteImportedRecording(dir.File("in.h5"), r.recording);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error.find("start_time_utc"), std::string::npos) << w.error;
  EXPECT_EQ(EntriesIn(dir.path()), 1);  // the source only
}

// Three samples pass the layout checks but not `run`'s (too few to analyse): the file is refused
// before it gets its name, so nothing under that name ever appears.
TEST(TextImport, AnOutputRunWouldRefuseForItsSamplesNeverAppears) {
  TempDir dir;
  const ImportResult r = ImportText(WriteText(dir, "in.txt", "1\n2\n3\n"), Options());
  ASSERT_TRUE(r.ok()) << r.error;
  const ImportWriteResult w = WriteImportedRecording(dir.File("in.h5"), r.recording);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error.find("too_few_samples"), std::string::npos) << w.error;
  EXPECT_EQ(EntriesIn(dir.path()), 1);  // the source only
}

TEST(TextImport, MissingFileAndFolderAreErrorsNamingThem) {
  TempDir dir;
  EXPECT_TRUE(
      Refused(ImportText(dir.File("none.csv"), Options()), "none.csv: cannot open for reading"));
  EXPECT_TRUE(Refused(ImportText(dir.path().string(), Options()), "is a folder"));
}

}  // namespace
}  // namespace fogpipe::io
