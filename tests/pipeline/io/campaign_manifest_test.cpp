// Tests of pipeline/io/campaign_manifest (fogpipe plan and the shards of a Slurm job array).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "pipeline/io/campaign_manifest.h"

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;

std::vector<io::InputFile> Inputs(const std::vector<std::uintmax_t>& sizes) {
  std::vector<io::InputFile> inputs;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    char name[48];
    std::snprintf(name, sizeof(name), "/data/run%03zu.h5", i);
    inputs.push_back({name, sizes[i], ""});
  }
  return inputs;
}

// Every shard scheme must partition the list: each file in exactly one shard, for any N,
// including more shards than files.
TEST(CampaignManifest, ShardsPartitionTheListForEveryScheme) {
  const auto inputs = Inputs({5, 900, 30, 30, 1, 400, 77, 2, 650, 8, 8, 120, 3});
  for (ShardBy by : {ShardBy::kStride, ShardBy::kSize}) {
    for (int n : {1, 2, 3, 4, 7, 13, 20}) {
      std::multiset<std::string> seen;
      for (int shard = 0; shard < n; ++shard) {
        const auto part = SelectShard(inputs, shard, n, by);
        EXPECT_TRUE(std::is_sorted(part.begin(), part.end(),
                                   [](const auto& a, const auto& b) { return a.path < b.path; }));
        for (const auto& f : part) seen.insert(f.path);
      }
      ASSERT_EQ(seen.size(), inputs.size()) << ToString(by) << " n=" << n;
      for (const auto& f : inputs) EXPECT_EQ(seen.count(f.path), 1u) << f.path;
    }
  }
}

TEST(CampaignManifest, StrideShardsTakeEveryNthFile) {
  const auto part = SelectShard(Inputs({1, 1, 1, 1, 1, 1, 1}), 1, 3, ShardBy::kStride);
  ASSERT_EQ(part.size(), 2u);
  EXPECT_EQ(part[0].path, "/data/run001.h5");
  EXPECT_EQ(part[1].path, "/data/run004.h5");
}

// Greedy longest-processing-time (Graham 1969): the largest shard is at most
// (4/3 - 1/(3N)) times the optimum, and the optimum is at least max(total / N, largest file).
TEST(CampaignManifest, SizeShardsAreWithinGrahamsBound) {
  const std::vector<std::uintmax_t> sizes = {5, 900, 30,  30, 1,   400, 77, 2, 650,
                                             8, 8,   120, 3,  310, 260, 90, 45};
  const auto inputs = Inputs(sizes);
  std::uintmax_t total = 0, largest = 0;
  for (auto s : sizes) total += s, largest = std::max(largest, s);
  for (int n : {2, 3, 4}) {
    std::uintmax_t worst = 0, worst_stride = 0;
    for (int shard = 0; shard < n; ++shard) {
      std::uintmax_t load = 0, stride = 0;
      for (const auto& f : SelectShard(inputs, shard, n, ShardBy::kSize)) load += f.size_bytes;
      for (const auto& f : SelectShard(inputs, shard, n, ShardBy::kStride)) stride += f.size_bytes;
      worst = std::max(worst, load);
      worst_stride = std::max(worst_stride, stride);
    }
    const double lower_bound = std::max(double(total) / n, double(largest));
    EXPECT_LE(worst, (4.0 / 3.0 - 1.0 / (3.0 * n)) * lower_bound + 1e-9) << "n=" << n;
    EXPECT_LE(worst, worst_stride) << "n=" << n;
  }
}

// The manifest `fogpipe plan` writes is read back by io::ListInputs (what `fogpipe run
// --manifest` uses) with the same sorted paths, and survives an empty-size fallback.
TEST(CampaignManifest, WrittenManifestReadsBackThroughListInputs) {
  const fs::path dir =
      fs::temp_directory_path() / ("fogpipe_manifest_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<io::InputFile> inputs;
  for (const char* name : {"b.h5", "a.h5", "c.h5"}) {
    std::ofstream(dir / name) << std::string(std::string(name) == "b.h5" ? 100 : 10, 'x');
  }
  std::vector<std::string> errors;
  inputs = io::ListInputs({dir.string()}, "", &errors);
  ASSERT_TRUE(errors.empty());
  std::string error;
  const std::string manifest = (dir / "manifest.txt").string();
  ASSERT_TRUE(WriteManifest(manifest, inputs, &error)) << error;
  const auto back = io::ListInputs({}, manifest, &errors);
  ASSERT_TRUE(errors.empty()) << errors.front();
  ASSERT_EQ(back.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].path, fs::absolute(inputs[i].path).lexically_normal().string());
    EXPECT_EQ(back[i].size_bytes, inputs[i].size_bytes);
    EXPECT_EQ(back[i].output_name, inputs[i].output_name);
  }
  EXPECT_EQ(back[1].size_bytes, 100u);
  std::ifstream in(manifest);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "# fogpipe-manifest-v1: 3 recordings, 120 bytes; columns: path size_bytes");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fogpipe::io
