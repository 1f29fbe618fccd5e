// `fogpipe validate` as a user runs it: output lines and exit codes 0 / 1 / 2.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/pipeline/io/run_fogpipe.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe {
namespace {

using testing::Quote;
using testing::RunFogpipe;

TEST(ValidateCommand, ExitsZeroForAValidRecordingAndSaysWhichSchemaItUsed) {
  testing::TempDir dir;
  const std::string path = dir.File("good.h5");
  testing::RecordingSpec spec;
  spec.temperature = true;
  testing::WriteRecording(path, spec);
  const auto r = RunFogpipe("validate " + Quote(path));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(path + ": valid recording (schema recording-v1"), std::string::npos)
      << r.output;
}

TEST(ValidateCommand, ExitsOneAndPrintsEachProblemWithFileAndObjectPath) {
  testing::TempDir dir;
  const std::string good = dir.File("good.h5");
  const std::string bad = dir.File("bad.h5");
  testing::WriteRecording(good, testing::RecordingSpec{});
  testing::RecordingSpec spec;
  spec.units = "degrees per hour";
  testing::WriteRecording(bad, spec);
  const auto r = RunFogpipe("validate " + Quote(good) + " " + Quote(bad));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(bad + ": INVALID (schema recording-v1), 1 problem"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("  " + bad + ": /rate: units 'degrees per hour' not allowed here"),
            std::string::npos)
      << r.output;
}

TEST(ValidateCommand, ExitsOneForAFileThatIsNotHdf5) {
  testing::TempDir dir;
  const std::string path = dir.File("x.h5");
  std::ofstream(path) << "hello";
  const auto r = RunFogpipe("validate " + Quote(path));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("[not_hdf5]"), std::string::npos) << r.output;
}

TEST(ValidateCommand, ExitsTwoOnUsageErrors) {
  testing::TempDir dir;
  const std::string path = dir.File("good.h5");
  testing::WriteRecording(path, testing::RecordingSpec{});
  EXPECT_EQ(RunFogpipe("validate").exit_code, 2);
  const auto r = RunFogpipe("validate --schemas " + Quote(dir.path().string()) + " " + Quote(path),
                            /*merge_stderr=*/true);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("schema 'recording-v1.json' not found"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace fogpipe
