#include "pipeline/io/campaign_manifest.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <system_error>

#include "pipeline/io/text_output_file.h"

namespace fogpipe::io {

namespace fs = std::filesystem;

const char* ToString(ShardBy by) { return by == ShardBy::kSize ? "size" : "stride"; }

bool ParseShardBy(const std::string& text, ShardBy* by) {
  if (text == "stride") {
    *by = ShardBy::kStride;
  } else if (text == "size") {
    *by = ShardBy::kSize;
  } else {
    return false;
  }
  return true;
}

std::string FormatManifest(const std::vector<InputFile>& inputs) {
  std::uintmax_t total = 0;
  for (const auto& input : inputs) total += input.size_bytes;
  std::ostringstream out;
  out << "# fogpipe-manifest-v1: " << inputs.size() << " recordings, " << total
      << " bytes; columns: path size_bytes\n";
  for (const auto& input : inputs) {
    std::error_code ec;
    fs::path path = fs::absolute(input.path, ec);
    if (ec) path = input.path;
    out << QuoteManifestPath(path.lexically_normal().string()) << " " << input.size_bytes << "\n";
  }
  return out.str();
}

bool WriteManifest(const std::string& path, const std::vector<InputFile>& inputs,
                   std::string* error) {
  try {
    WriteTextFileAtomically(path, FormatManifest(inputs));
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
  return true;
}

std::vector<InputFile> SelectShard(const std::vector<InputFile>& inputs, int shard, int num_shards,
                                   ShardBy by) {
  if (num_shards <= 1) return inputs;
  if (by == ShardBy::kStride) {
    std::vector<InputFile> selected;
    for (std::size_t i = static_cast<std::size_t>(shard); i < inputs.size();
         i += static_cast<std::size_t>(num_shards)) {
      selected.push_back(inputs[i]);
    }
    return selected;
  }
  std::vector<std::size_t> order(inputs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return inputs[a].size_bytes > inputs[b].size_bytes;  // stable: ties keep path order
  });
  std::vector<std::uintmax_t> load(static_cast<std::size_t>(num_shards), 0);
  std::vector<bool> mine(inputs.size(), false);
  for (std::size_t i : order) {
    const auto lightest =
        static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    load[static_cast<std::size_t>(lightest)] += inputs[i].size_bytes;
    mine[i] = lightest == shard;
  }
  std::vector<InputFile> selected;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (mine[i]) selected.push_back(inputs[i]);
  }
  return selected;
}

}  // namespace fogpipe::io
