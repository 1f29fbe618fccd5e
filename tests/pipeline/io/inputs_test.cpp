// Tests of pipeline/io/inputs: the campaign input list (files, folders, globs, manifests) and
// its output names.
#include "pipeline/io/inputs.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "pipeline/io/campaign_manifest.h"

namespace fogpipe::io {
namespace {
namespace fs = std::filesystem;

class InputsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per process: ctest runs every TEST as its own process, in parallel, and a shared
    // folder would be removed by one test's TearDown under another.
    root_ = fs::path(::testing::TempDir()) / ("fogpipe_inputs_test_" + std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "a" / "deep");
    fs::create_directories(root_ / "b");
    for (const char* f : {"a/x.h5", "a/deep/y.h5", "a/notes.txt", "b/x.h5", "b/z.h5"}) {
      std::ofstream(root_ / f) << "0123456789";
    }
  }
  void TearDown() override { fs::remove_all(root_); }
  std::string P(const char* relative) const { return (root_ / relative).string(); }
  fs::path root_;
};

TEST_F(InputsTest, ExpandsFoldersRecursivelyGlobsAndFilesSortedWithoutDuplicates) {
  std::vector<std::string> errors;
  const auto inputs = ListInputs({P("a"), P("b/*.h5"), P("b/z.h5")}, "", &errors);
  EXPECT_TRUE(errors.empty());
  ASSERT_EQ(inputs.size(), 4u);
  EXPECT_EQ(inputs[0].path, P("a/deep/y.h5"));
  EXPECT_EQ(inputs[1].path, P("a/x.h5"));
  EXPECT_EQ(inputs[3].path, P("b/z.h5"));
  EXPECT_EQ(inputs[3].size_bytes, 10u);
}

TEST_F(InputsTest, GivesCollidingStemsDistinctStableOutputNames) {
  std::vector<std::string> errors;
  const auto inputs = ListInputs({P("a/x.h5"), P("b/x.h5"), P("b/z.h5")}, "", &errors);
  ASSERT_EQ(inputs.size(), 3u);
  EXPECT_NE(inputs[0].output_name, inputs[1].output_name);
  EXPECT_EQ(inputs[0].output_name.rfind("x-", 0), 0u);
  EXPECT_EQ(inputs[2].output_name, "z.fogpipe.h5");
  // Stable: the same input gets the same name whatever else is listed with it.
  const auto again = ListInputs({P("b/x.h5"), P("a/x.h5")}, "", &errors);
  EXPECT_EQ(again[0].output_name, inputs[0].output_name);
}

TEST_F(InputsTest, ReadsAManifestWithCommentsSizesAndRelativePaths) {
  std::ofstream(root_ / "list.txt") << "# campaign\n\na/x.h5 10\n"
                                    << P("b/z.h5") << "  # abs\n"
                                    << "missing.h5 123\n"
                                    << "b/x.h5 notasize\n";
  std::vector<std::string> errors;
  const auto inputs = ListInputs({}, P("list.txt"), &errors);
  ASSERT_EQ(inputs.size(), 3u);
  EXPECT_EQ(inputs[2].path, P("missing.h5"));
  EXPECT_EQ(inputs[2].size_bytes, 123u);  // the manifest's size when the file cannot be stat'ed
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("list.txt:6"), std::string::npos) << errors[0];
}

// Paths with spaces, '#', quotes and backslashes survive `fogpipe plan`'s manifest and
// `run --manifest`: FormatManifest quotes them and ListInputs reads them back unchanged.
TEST_F(InputsTest, ManifestPathsWithSpacesHashesQuotesAndLineBreaksRoundTrip) {
  for (const char* f : {"b/run 2.h5", "b/run#3.h5", "b/q\"uo\\te.h5", "b/plain.h5",
                        "b/line\nbreak.h5", "b/cr\rname.h5"})
    std::ofstream(root_ / f) << "0123456789";
  std::vector<std::string> errors;
  const auto listed = ListInputs({P("b")}, "", &errors);
  ASSERT_TRUE(errors.empty());
  ASSERT_EQ(listed.size(), 8u);
  std::ofstream(root_ / "plan.txt") << io::FormatManifest(listed);
  const auto read = ListInputs({}, P("plan.txt"), &errors);
  EXPECT_TRUE(errors.empty()) << errors.front();
  ASSERT_EQ(read.size(), listed.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].path, listed[i].path);
    EXPECT_EQ(read[i].size_bytes, 10u);
  }
}

TEST(ManifestLine, ReadsQuotedPathsSizesAndCommentsOnlyWhereAFieldStarts) {
  EXPECT_TRUE(ParseManifestLine("   # only a comment").empty);
  EXPECT_TRUE(ParseManifestLine("").empty);
  ManifestLine l = ParseManifestLine("run#3.h5 42 # note");
  EXPECT_EQ(l.path, "run#3.h5");
  EXPECT_EQ(l.size, "42");
  l = ParseManifestLine(R"("a b/c \"d\".h5" 7)");
  EXPECT_EQ(l.path, "a b/c \"d\".h5");
  EXPECT_EQ(l.size, "7");
  EXPECT_EQ(QuoteManifestPath("a b/c \"d\".h5"), R"("a b/c \"d\".h5")");
  EXPECT_EQ(QuoteManifestPath("/plain/x.h5"), "/plain/x.h5");
  EXPECT_NE(ParseManifestLine("\"open quote.h5 1").error.find("unterminated"), std::string::npos);
  EXPECT_NE(ParseManifestLine("my file.h5 1").error.find("double quotes"), std::string::npos);
  EXPECT_NE(ParseManifestLine("x.h5 1 extra").error.find("extra text"), std::string::npos);
}

TEST_F(InputsTest, ReportsPatternsAndFoldersThatMatchNothing) {
  std::vector<std::string> errors;
  fs::create_directories(root_ / "empty");
  const auto inputs = ListInputs({P("empty"), P("nothing*.h5")}, "", &errors);
  EXPECT_TRUE(inputs.empty());
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_NE(errors[0].find("empty"), std::string::npos);
}

}  // namespace
}  // namespace fogpipe::io
