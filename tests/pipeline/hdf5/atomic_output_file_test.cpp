#include "pipeline/hdf5/atomic_output_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "pipeline/hdf5/hdf5_lock.h"
#include "tests/pipeline/io/test_recording_files.h"

namespace fogpipe::hdf5 {
namespace {

namespace fs = std::filesystem;
using fogpipe::testing::TempDir;

std::vector<std::string> Listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(AtomicOutputFile, WritesUnderATempNameInTheSameFolderAndRenamesOnCommit) {
  TempDir dir;
  const fs::path final_path = dir.path() / "out.fogpipe.h5";
  auto lock = LockHdf5();
  AtomicOutputFile out(final_path);
  EXPECT_EQ(out.temp_path().parent_path(), final_path.parent_path());
  EXPECT_TRUE(IsAtomicTempName(out.temp_path()));
  out.Root().WriteDoubleAttribute("answer", 42.0);
  EXPECT_FALSE(fs::exists(final_path));
  EXPECT_TRUE(fs::exists(out.temp_path()));
  out.Commit();
  EXPECT_TRUE(out.committed());
  EXPECT_EQ(Listing(dir.path()), (std::vector<std::string>{"out.fogpipe.h5"}));
  File back = File::OpenReadOnly(final_path.string());
  EXPECT_EQ(back.Root().ReadDoubleAttribute("answer"), 42.0);
}

TEST(AtomicOutputFile, RemovesTheTempFileWhenNotCommitted) {
  TempDir dir;
  const fs::path final_path = dir.path() / "out.h5";
  auto lock = LockHdf5();
  try {
    AtomicOutputFile out(final_path);
    out.Root().WriteDoubleAttribute("partial", 1.0);
    throw std::runtime_error("analysis failed halfway");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(Listing(dir.path()).empty());
}

TEST(AtomicOutputFile, ReplacesAnOlderOutputOnlyAtCommit) {
  TempDir dir;
  const fs::path final_path = dir.path() / "out.h5";
  auto lock = LockHdf5();
  {
    AtomicOutputFile first(final_path);
    first.Root().WriteInt64Attribute("version", 1);
    first.Commit();
  }
  {
    AtomicOutputFile second(final_path);
    second.Root().WriteInt64Attribute("version", 2);
    EXPECT_EQ(File::OpenReadOnly(final_path.string()).Root().ReadInt64Attribute("version"), 1);
    second.Commit();
  }
  EXPECT_EQ(File::OpenReadOnly(final_path.string()).Root().ReadInt64Attribute("version"), 2);
  EXPECT_EQ(Listing(dir.path()).size(), 1u);
}

TEST(AtomicOutputFile, TwoWritersOfTheSameTargetNeverShareATempFile) {
  TempDir dir;
  auto lock = LockHdf5();
  AtomicOutputFile a(dir.path() / "x.h5");
  AtomicOutputFile b(dir.path() / "x.h5");
  EXPECT_NE(a.temp_path(), b.temp_path());
}

TEST(AtomicOutputFile, RecognisesItsTempNamesAndNothingElse) {
  EXPECT_TRUE(IsAtomicTempName("/a/b/run.fogpipe.h5.tmp-1234-0"));
  EXPECT_TRUE(IsAtomicTempName(MakeAtomicTempPath("/a/out.h5")));
  EXPECT_FALSE(IsAtomicTempName("/a/out.h5"));
  EXPECT_FALSE(IsAtomicTempName("/a/out.tmp-x-1"));
  EXPECT_FALSE(IsAtomicTempName("/a/out.tmp-12"));
  EXPECT_FALSE(IsAtomicTempName("/a/.tmp-1-2"));
}

}  // namespace
}  // namespace fogpipe::hdf5
