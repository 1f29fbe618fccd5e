// Tests of pipeline/io/schema_validator (the engine, on small inline schemas) and of
// schemas/recording-v1.json through pipeline/io/file_validation.
#include "pipeline/io/schema_validator.h"

#include <H5Lpublic.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <fstream>

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/file_validation.h"
#include "pipeline/io/isolated_reader.h"
#include "pipeline/io/recording_check.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::io {
namespace {

using testing::RawFile;
using testing::RecordingSpec;
using testing::TempDir;

const std::string kSchemasDir = std::string(FOGPIPE_SOURCE_DIR) + "/schemas";

std::vector<double> Signal(int n) {
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(testing::TestValue(k, 0));
  return v;
}

/// All problem lines "object: message" of a validation, for readable assertions.
std::string Lines(const std::vector<SchemaProblem>& problems) {
  std::string text;
  for (const auto& p : problems) text += p.object + ": " + p.message + "\n";
  return text;
}

FileValidation ValidateRecording(const std::string& path) {
  FileValidationOptions options;
  options.schemas_dir = kSchemasDir;
  return ValidateFile(path, options);
}

// ------------------------------------------------------------------ recording-v1.json

TEST(RecordingSchema, AcceptsEveryKindOfContractRecording) {
  TempDir dir;
  int i = 0;
  for (bool two_d : {false, true}) {
    for (const std::string units : {"deg/h", "deg/s", "rad/s"}) {
      RecordingSpec spec;
      spec.two_dimensional = two_d;
      spec.axes = two_d ? 3 : 1;
      spec.units = units;
      spec.temperature = (i % 2) == 0;
      spec.layout = {H5T_IEEE_F32LE, {}, 0, false};
      if (two_d) spec.axis_names = {"x", "y", "z"};
      const std::string path = dir.File("ok" + std::to_string(i++) + ".h5");
      testing::WriteRecording(path, spec);
      const FileValidation v = ValidateRecording(path);
      EXPECT_TRUE(v.valid()) << path << "\n" << Lines(v.problems) << v.usage_error;
      EXPECT_EQ(v.schema, "recording-v1");
      EXPECT_EQ(v.samples_checked, 1000 * spec.axes + (spec.temperature ? 1000 : 0));
      EXPECT_NO_THROW(InspectRecording(path)) << path;
    }
  }
}

struct LayoutCase {
  std::string name;
  std::function<void(RawFile&)> make;
  std::string expected;  ///< a line of the report
};

void PrintTo(const LayoutCase& c, std::ostream* os) { *os << c.name; }

void RateOk(RawFile& f) {
  f.Dataset("/rate", {100}, Signal(100));
  f.StringAttribute("/rate", "units", "rad/s");
}

class RecordingSchemaRejects : public ::testing::TestWithParam<LayoutCase> {};

// Validates a recording built by `make` (a rate dataset with units is already there).
FileValidation ValidateMade(const std::string& name, const std::function<void(RawFile&)>& make) {
  TempDir dir;
  const std::string path = dir.File(name);
  {
    RawFile file(path);
    RateOk(file);
    make(file);
  }
  return ValidateRecording(path);
}

// An integer sample rate is read as the same rate by `run` (recording_reader.h); `validate`
// agrees, so the two commands give one verdict on the same file.
TEST(RecordingSchema, AcceptsAnIntegerSampleRateAsRunReadsIt) {
  TempDir dir;
  const std::string path = dir.File("integer_rate.h5");
  {
    RawFile f(path);
    RateOk(f);
    f.IntAttribute("/", "sample_rate_hz", 100);
  }
  const FileValidation v = ValidateRecording(path);
  EXPECT_TRUE(v.valid()) << Lines(v.problems) << v.usage_error;
  EXPECT_EQ(InspectRecording(path).sample_rate_hz, 100.0);
}

// A soft-link cycle (/g/loop -> /g) is harmless to `run`, which never looks there; the validator
// does not follow soft links into groups, so it neither loops nor exhausts its memory.
TEST(RecordingSchema, ASoftLinkCycleIsNotFollowed) {
  const FileValidation v = ValidateMade("cycle.h5", [](RawFile& f) {
    f.DoubleAttribute("/", "sample_rate_hz", 10.0);
    f.Group("/g");
    EXPECT_GE(H5Lcreate_soft("/g", f.id(), "/g/loop", H5P_DEFAULT, H5P_DEFAULT), 0);
  });
  EXPECT_TRUE(v.valid()) << Lines(v.problems) << v.usage_error;
}

// An external link is reported, not followed, even where the layout ignores unknown objects:
// following it would open another file. Its target here is a FIFO, on which opening blocks, so a
// validator that followed it would hang until the child's time limit.
TEST(RecordingSchema, ReportsAnExternalLinkWithoutOpeningItsTarget) {
  TempDir dir;
  const std::string fifo = dir.File("target.h5");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string path = dir.File("elink.h5");
  {
    RawFile f(path);
    RateOk(f);
    f.DoubleAttribute("/", "sample_rate_hz", 10.0);
    ASSERT_GE(H5Lcreate_external(fifo.c_str(), "/rate", f.id(), "hidden", H5P_DEFAULT, H5P_DEFAULT),
              0);
  }
  FileValidationOptions options;
  options.schemas_dir = kSchemasDir;
  IsolationLimits limits;
  limits.seconds = 5.0;
  const FileValidation v = ValidateFileIsolated(path, options, limits);
  EXPECT_FALSE(v.valid());
  EXPECT_NE(Lines(v.problems).find("/hidden: is reached through an external link"),
            std::string::npos)
      << Lines(v.problems);
  EXPECT_EQ(Lines(v.problems).find("reader_timeout"), std::string::npos) << Lines(v.problems);
  try {
    InspectRecordingIsolated(path, limits);
    ADD_FAILURE() << "the reading commands accept a file with an external link";
  } catch (const RecordingError& e) {
    EXPECT_EQ(e.kind(), error_kind::kLayoutViolation) << e.what();
  }
}

TEST_P(RecordingSchemaRejects, WithAMessageNamingTheObjectAndTheProblem) {
  TempDir dir;
  const std::string path = dir.File(GetParam().name + ".h5");
  {
    RawFile file(path);
    GetParam().make(file);
  }
  const FileValidation v = ValidateRecording(path);
  EXPECT_FALSE(v.valid());
  EXPECT_TRUE(v.usage_error.empty()) << v.usage_error;
  EXPECT_NE(Lines(v.problems).find(GetParam().expected), std::string::npos)
      << "report:\n"
      << Lines(v.problems) << "expected a line containing: " << GetParam().expected;
}

// `validate` and the commands that analyse recordings give one verdict: what the first refuses,
// the reader refuses too, at inspection (the metadata) or when the axes are read (the samples).
TEST_P(RecordingSchemaRejects, AndTheAnalysingCommandsRefuseItToo) {
  TempDir dir;
  const std::string path = dir.File(GetParam().name + ".h5");
  {
    RawFile file(path);
    GetParam().make(file);
  }
  try {
    const RecordingInfo info = InspectRecording(path);
    for (int axis = 0; axis < info.axis_count; ++axis) {
      ReadAxisRadPerSecond(path, std::to_string(axis));
    }
    ADD_FAILURE() << GetParam().name << ": validate refuses it, the reader accepts it";
  } catch (const RecordingError& e) {
    EXPECT_FALSE(e.kind().empty());
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    RecordingSchema, RecordingSchemaRejects,
    ::testing::Values(
        LayoutCase{"no_rate", [](RawFile& f) { f.DoubleAttribute("/", "sample_rate_hz", 1.0); },
                   "/: missing required dataset 'rate'"},
        LayoutCase{"no_sample_rate", [](RawFile& f) { RateOk(f); },
                   "/: missing required attribute 'sample_rate_hz'"},
        LayoutCase{"negative_sample_rate",
                   [](RawFile& f) {
                     RateOk(f);
                     f.DoubleAttribute("/", "sample_rate_hz", -100.0);
                   },
                   "/: attribute 'sample_rate_hz' is -100, expected > 0"},
        LayoutCase{"infinite_sample_rate",
                   [](RawFile& f) {
                     RateOk(f);
                     f.DoubleAttribute("/", "sample_rate_hz", HUGE_VAL);
                   },
                   "/: attribute 'sample_rate_hz' is inf, expected a finite number"},
        LayoutCase{"string_sample_rate",
                   [](RawFile& f) {
                     RateOk(f);
                     f.StringAttribute("/", "sample_rate_hz", "100");
                   },
                   "/: attribute 'sample_rate_hz' has type string, expected number"},
        LayoutCase{"bad_units",
                   [](RawFile& f) {
                     f.Dataset("/rate", {100}, Signal(100));
                     f.StringAttribute("/rate", "units", "dps");
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "/rate: units 'dps' not allowed here (allowed: deg/h, deg/s, rad/s)"},
        LayoutCase{"no_units",
                   [](RawFile& f) {
                     f.Dataset("/rate", {100}, Signal(100));
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "/rate: numeric dataset has no 'units' attribute"},
        LayoutCase{"string_scale_factor",
                   [](RawFile& f) {
                     f.Dataset("/rate", {100}, Signal(100), {H5T_STD_I16LE, {}, 0, false});
                     f.StringAttribute("/rate", "units", "rad/s");
                     f.StringAttribute("/rate", "scale_factor", "0.01");
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "/rate: attribute 'scale_factor'"},
        LayoutCase{"rank_3",
                   [](RawFile& f) {
                     f.Dataset("/rate", {10, 5, 2}, Signal(100));
                     f.StringAttribute("/rate", "units", "rad/s");
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "/rate: has rank 3, expected rank 1 or 2"},
        LayoutCase{"axes_length",
                   [](RawFile& f) {
                     f.Dataset("/rate", {50, 2}, Signal(100));
                     f.StringAttribute("/rate", "units", "rad/s");
                     f.StringArrayAttribute("/rate", "axes", {"x"});
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "/rate: attribute 'axes' has 1 elements, expected 2 (the dataset's extent in "
                   "dimension 1)"},
        LayoutCase{"bad_start_time",
                   [](RawFile& f) {
                     RateOk(f);
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                     f.StringAttribute("/", "start_time_utc", "yesterday at 8");
                   },
                   "/: attribute 'start_time_utc' is 'yesterday at 8', which does not match"},
        LayoutCase{"latitude_out_of_range",
                   [](RawFile& f) {
                     RateOk(f);
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                     f.DoubleAttribute("/", "latitude_deg", 123.0);
                   },
                   "/: attribute 'latitude_deg' is 123, expected <= 90"},
        LayoutCase{"aux_short",
                   [](RawFile& f) {
                     RateOk(f);
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                     f.Dataset("/aux/temperature", {99}, std::vector<double>(99, 20.0));
                     f.StringAttribute("/aux/temperature", "units", "degC");
                   },
                   "/aux/temperature: has 99 rows but /rate has 100"},
        LayoutCase{"aux_without_units",
                   [](RawFile& f) {
                     RateOk(f);
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                     f.Dataset("/aux/temperature", {100}, std::vector<double>(100, 20.0));
                   },
                   "/aux/temperature: numeric dataset has no 'units' attribute"},
        LayoutCase{"rate_is_group",
                   [](RawFile& f) {
                     f.Group("/rate");
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "/rate: is a group, expected a dataset"},
        // Layout fine, data not: the reader's semantic checks run after the schema.
        LayoutCase{"long_nan_gap",
                   [](RawFile& f) {
                     std::vector<double> v = Signal(100);
                     for (int k = 10; k < 40; ++k) v[k] = std::nan("");
                     f.Dataset("/rate", {100}, v);
                     f.StringAttribute("/rate", "units", "rad/s");
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "/rate: /rate axis 'axis0' has a run of 30 missing (NaN) samples"},
        // The contract sets no minimum length; the analysis does, and validate uses its limit.
        LayoutCase{"63_samples",
                   [](RawFile& f) {
                     f.Dataset("/rate", {63}, Signal(63));
                     f.StringAttribute("/rate", "units", "rad/s");
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "[too_few_samples]"},
        LayoutCase{"constant",
                   [](RawFile& f) {
                     f.Dataset("/rate", {100}, std::vector<double>(100, 1.5));
                     f.StringAttribute("/rate", "units", "rad/s");
                     f.DoubleAttribute("/", "sample_rate_hz", 1.0);
                   },
                   "[constant_signal]"}),
    [](const auto& info) { return info.param.name; });

TEST(FileValidation, ReportsFilesThatAreNotHdf5AsInvalidNotAsUsageErrors) {
  TempDir dir;
  const std::string path = dir.File("notes.h5");
  std::ofstream(path) << "not hdf5";
  const FileValidation v = ValidateRecording(path);
  EXPECT_TRUE(v.usage_error.empty());
  ASSERT_EQ(v.problems.size(), 1u);
  EXPECT_NE(v.problems[0].message.find("[not_hdf5]"), std::string::npos);
}

// A file's own attribute may name a schema, never a path: a tag that names no known format is
// that file's problem (the command goes on with the next file), and nothing it names is opened.
TEST(FileValidation, AFormatTagThatNamesAPathOrNoFormatIsTheFilesProblem) {
  TempDir dir;
  for (const std::string tag : {"/etc/passwd", "../schemas/recording-v1.json", "foo"}) {
    const std::string path = dir.File("tagged.h5");
    {
      RawFile f(path);
      RateOk(f);
      f.DoubleAttribute("/", "sample_rate_hz", 10.0);
      f.StringAttribute("/", "fogpipe_format", tag);
    }
    const FileValidation v = ValidateRecording(path);
    EXPECT_TRUE(v.usage_error.empty()) << tag << ": " << v.usage_error;
    EXPECT_NE(Lines(v.problems).find("names no fogpipe file format"), std::string::npos)
        << tag << ": " << Lines(v.problems);
    EXPECT_TRUE(v.schema_path.empty()) << tag << ": " << v.schema_path;
    // The reading commands refuse it too: one verdict.
    EXPECT_THROW(InspectRecording(path), RecordingError) << tag;
  }
}

TEST(FileValidation, PicksTheSchemaFromTheFormatTagAndFailsCleanlyWhenItIsMissing) {
  EXPECT_EQ(SchemaNameForFormat(""), "recording-v1");
  EXPECT_EQ(SchemaNameForFormat("fogpipe-results-v2"), "results-v2");
  TempDir dir;
  const std::string path = dir.File("r.fogpipe.h5");
  {
    RawFile f(path);
    f.StringAttribute("/", "fogpipe_format", "fogpipe-results-v2");
  }
  FileValidationOptions options;
  options.schemas_dir = dir.path().string();  // holds no schema
  FileValidation v = ValidateFile(path, options);
  EXPECT_EQ(v.detected, "fogpipe-results-v2");
  EXPECT_NE(v.usage_error.find("schema 'results-v2.json' not found"), std::string::npos);
  std::ofstream(dir.File("results-v2.json"))
      << R"({"format": "fogpipe-schema-v1", "name": "results-v2", "root": {
             "attributes": {"fogpipe_format": {"required": true, "type": "string",
                                               "enum": ["fogpipe-results-v2"]}},
             "groups": {"provenance": {"required": true}}}})";
  v = ValidateFile(path, options);
  EXPECT_TRUE(v.usage_error.empty()) << v.usage_error;
  EXPECT_EQ(Lines(v.problems), "/: missing required group 'provenance'\n");
}

// A file of the previous results layout is named as such, whatever schemas are around: it is a
// problem of the file (validate exits 1, a rerun rewrites it), not a missing schema.
TEST(FileValidation, NamesThePreviousResultsLayoutInsteadOfLookingForItsSchema) {
  TempDir dir;
  const std::string path = dir.File("old.fogpipe.h5");
  {
    RawFile f(path);
    f.StringAttribute("/", "fogpipe_format", "fogpipe-results-v1");
  }
  FileValidationOptions options;
  options.schemas_dir = kSchemasDir;
  const FileValidation v = ValidateFile(path, options);
  EXPECT_TRUE(v.usage_error.empty()) << v.usage_error;
  EXPECT_NE(Lines(v.problems).find("previous results layout"), std::string::npos)
      << Lines(v.problems);
  EXPECT_NE(Lines(v.problems).find("fogpipe-results-v2"), std::string::npos) << Lines(v.problems);
}

// ------------------------------------------------------------------ the engine

/// A results-like layout exercising patterns, counts, forbid and the units rule.
const char* kEngineSchema = R"({
  "format": "fogpipe-schema-v1",
  "name": "engine-test",
  "every_numeric_dataset_has_units": true,
  "root": {
    "additional": "forbid",
    "attributes": {"version": {"required": true, "type": "integer", "enum": [1, 2]}},
    "groups": {
      "axes": {
        "required": true,
        "groups": {
          "<axis>": {
            "min_count": 1,
            "groups": {
              "imfs": {
                "required": true,
                "additional": "forbid",
                "datasets": {
                  "imf_<k:int>": {"type": "float", "rank": 1, "min_count": 2, "max_count": 3,
                                  "units": ["rad/s"]},
                  "residue": {"required": true, "type": "float", "units": ["rad/s"]}
                }
              }
            }
          }
        }
      }
    }
  }
})";

class SchemaEngine : public ::testing::Test {
 protected:
  void SetUp() override { hdf5::SilenceHdf5ErrorPrinter(); }
  std::string Report(const std::function<void(RawFile&)>& make) {
    const std::string path = dir_.File("f" + std::to_string(n_++) + ".h5");
    {
      RawFile f(path);
      make(f);
    }
    const Schema schema = Schema::FromJsonText(kEngineSchema, "engine-test");
    auto lock = hdf5::LockHdf5();
    const hdf5::File file = hdf5::File::OpenReadOnly(path);
    return Lines(schema.Validate(file).problems);
  }
  static void Imf(RawFile& f, const std::string& path, const std::string& units = "rad/s") {
    f.Dataset(path, {10}, Signal(10));
    if (!units.empty()) f.StringAttribute(path, "units", units);
  }
  TempDir dir_;
  int n_ = 0;
};

TEST_F(SchemaEngine, AcceptsAFileThatFollowsTheLayout) {
  EXPECT_EQ(Report([](RawFile& f) {
              f.IntAttribute("/", "version", 2);
              Imf(f, "/axes/x/imfs/imf_0");
              Imf(f, "/axes/x/imfs/imf_1");
              Imf(f, "/axes/x/imfs/residue");
              Imf(f, "/axes/y/imfs/imf_0");
              Imf(f, "/axes/y/imfs/imf_1");
              Imf(f, "/axes/y/imfs/imf_2");
              Imf(f, "/axes/y/imfs/residue");
            }),
            "");
}

TEST_F(SchemaEngine, CountsRepeatedObjectsMatchedByAPattern) {
  const std::string report = Report([](RawFile& f) {
    f.IntAttribute("/", "version", 1);
    Imf(f, "/axes/x/imfs/imf_0");
    Imf(f, "/axes/x/imfs/residue");
    for (int k = 0; k < 4; ++k) Imf(f, "/axes/y/imfs/imf_" + std::to_string(k));
    Imf(f, "/axes/y/imfs/residue");
  });
  EXPECT_NE(report.find("/axes/x/imfs: has 1 dataset 'imf_<k:int>', expected at least 2"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("/axes/y/imfs: has 4 dataset 'imf_<k:int>', expected at most 3"),
            std::string::npos)
      << report;
}

// A table of files (fogpipe merge's /results) links to them: a described external link is
// counted and its target checked without opening the file; an undescribed one stays a problem.
// Columns of a table inside a repeated group are compared with a sibling.
TEST(SchemaLinks, DescribedExternalLinksAreCountedNotFollowedAndSiblingLengthsCompared) {
  hdf5::SilenceHdf5ErrorPrinter();
  TempDir dir;
  const std::string fifo = dir.File("blocks.h5");  // opening it would block
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string path = dir.File("table.h5");
  {
    RawFile f(path);
    f.Group("/results");
    for (const char* name : {"a", "b", "c"}) {
      ASSERT_GE(
          H5Lcreate_external(fifo.c_str(), std::string(name) == "c" ? "/other" : "/", f.id(),
                             (std::string("/results/") + name).c_str(), H5P_DEFAULT, H5P_DEFAULT),
          0);
    }
    ASSERT_GE(H5Lcreate_external(fifo.c_str(), "/", f.id(), "/stray", H5P_DEFAULT, H5P_DEFAULT), 0);
    f.Dataset("/rows/x/first", {10}, Signal(10));
    f.StringAttribute("/rows/x/first", "units", "1");
    f.Dataset("/rows/x/second", {9}, Signal(9));
    f.StringAttribute("/rows/x/second", "units", "1");
  }
  const Schema schema = Schema::FromJsonText(R"({
    "format": "fogpipe-schema-v1", "name": "links",
    "root": {"groups": {
      "results": {"required": true, "links": {"<name>": {"min_count": 4, "target": "/"}}},
      "rows": {"groups": {"<row>": {"datasets": {
        "first": {"required": true},
        "second": {"required": true, "same_length_as": "first"}}}}}}}})",
                                             "links.json");
  auto lock = hdf5::LockHdf5();
  const std::string report = Lines(schema.Validate(hdf5::File::OpenReadOnly(path)).problems);
  EXPECT_NE(report.find("/results/c: external link to '/other' in " + fifo + ", expected '/'"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("/results: has 3 external link '<name>', expected at least 4"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("/stray: is reached through an external link"), std::string::npos)
      << report;
  EXPECT_NE(report.find("/rows/x/second: has 9 rows but /rows/x/first has 10"), std::string::npos)
      << report;
  EXPECT_EQ(report.find("/results/a"), std::string::npos) << report;
}

// A table (compound dataset) is held to its fields: each required one present, of its type.
TEST(SchemaTables, ATableMissesAFieldOrHasOneOfAnotherType) {
  hdf5::SilenceHdf5ErrorPrinter();
  TempDir dir;
  const std::string path = dir.File("table.h5");
  {
    auto lock = hdf5::LockHdf5();
    hdf5::File file = hdf5::File::Create(path);
    hdf5::Group root = file.Root();
    root.WriteTable("good", {hdf5::TableColumn::Strings("name", {"Q"}),
                             hdf5::TableColumn::Doubles("value", {1.0})});
    root.WriteTable("bad", {hdf5::TableColumn::Strings("name", {"Q"}),
                            hdf5::TableColumn::Strings("value", {"1.0"})});
    root.WriteTable("short", {hdf5::TableColumn::Strings("name", {"Q"})});
    file.Close();
  }
  const std::string fields = R"("type": "compound", "rank": 1, "fields": {
      "name": {"type": "string"}, "value": {"type": "float"},
      "note": {"type": "string", "required": false}})";
  const Schema schema = Schema::FromJsonText(
      R"({"format": "fogpipe-schema-v1", "name": "tables", "every_numeric_dataset_has_units": true,
          "root": {"datasets": {"good": {)" +
          fields + R"(}, "bad": {)" + fields + R"(}, "short": {)" + fields + R"(}}}})",
      "tables");
  auto lock = hdf5::LockHdf5();
  const hdf5::File file = hdf5::File::OpenReadOnly(path);
  EXPECT_EQ(Lines(schema.Validate(file).problems),
            "/bad: field 'value' has type string, expected float\n"
            "/short: missing required field 'value'\n");
}

// The layouts of every HDF5 file fogpipe writes ship with it and parse.
TEST(ShippedSchemas, EveryOutputLayoutLoads) {
  for (const char* name : {"recording-v1", "results-v2", "campaign-v1", "sweep-v1", "compare-v1"}) {
    const std::string file = FindSchemaFile(name, kSchemasDir);
    ASSERT_FALSE(file.empty()) << name;
    EXPECT_EQ(Schema::FromFile(file).name(), name);
  }
}

TEST_F(SchemaEngine, ForbidsUnknownObjectsWhereTheSchemaSaysSoAndRequiresUnitsEverywhere) {
  const std::string report = Report([](RawFile& f) {
    f.IntAttribute("/", "version", 3);
    Imf(f, "/axes/x/imfs/imf_0");
    Imf(f, "/axes/x/imfs/imf_1", "deg/h");
    Imf(f, "/axes/x/imfs/imf_x");  // not an integer index
    Imf(f, "/axes/x/imfs/residue");
    Imf(f, "/axes/x/notes", "");  // unknown place, but numeric without units
    f.Group("/extra");
  });
  EXPECT_NE(report.find("/: attribute 'version' is 3, not one of the allowed values"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("/axes/x/imfs/imf_1: units 'deg/h' not allowed here"), std::string::npos)
      << report;
  EXPECT_NE(report.find("/axes/x/imfs/imf_x: unexpected dataset"), std::string::npos) << report;
  EXPECT_NE(report.find("/axes/x/notes: numeric dataset has no 'units' attribute"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("/extra: unexpected group"), std::string::npos) << report;
}

TEST_F(SchemaEngine, ReportsMissingRequiredObjectsAndWrongKinds) {
  const std::string report = Report([](RawFile& f) {
    Imf(f, "/axes/x/imfs/imf_0");
    Imf(f, "/axes/x/imfs/imf_1");
    f.Group("/axes/x/imfs/residue");
  });
  EXPECT_NE(report.find("/: missing required attribute 'version'"), std::string::npos) << report;
  EXPECT_NE(report.find("/axes/x/imfs/residue: is a group, expected a dataset"), std::string::npos)
      << report;
}

TEST(SchemaParsing, RejectsMalformedSchemasWithTheirLocation) {
  auto error_of = [](const std::string& text) {
    try {
      Schema::FromJsonText(text, "s.json");
    } catch (const SchemaError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("{").find("not valid JSON"), std::string::npos);
  EXPECT_NE(error_of(R"({"format": "x", "name": "n", "root": {}})").find("'format' must be"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"format": "fogpipe-schema-v1", "name": "n",
                         "root": {"datasets": {"rate": {"requird": true}}}})")
                .find("root/rate: unknown key 'requird'"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"format": "fogpipe-schema-v1", "name": "n",
                         "root": {"datasets": {"rate": {"type": "double"}}}})")
                .find("unknown type 'double'"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"format": "fogpipe-schema-v1", "name": "n",
                         "root": {"groups": {"imf_<k:real>": {}}}})")
                .find("unknown placeholder kind 'real'"),
            std::string::npos);
}

TEST(SchemaParsing, TheRecordingSchemaInTheSourceTreeParses) {
  const Schema schema = Schema::FromFile(kSchemasDir + "/recording-v1.json");
  EXPECT_EQ(schema.name(), "recording-v1");
  EXPECT_EQ(FindSchemaFile("recording-v1", kSchemasDir), kSchemasDir + "/recording-v1.json");
}

}  // namespace
}  // namespace fogpipe::io
