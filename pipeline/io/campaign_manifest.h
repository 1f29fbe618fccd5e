// The campaign manifest written by `fogpipe plan` and read by `fogpipe run --manifest` (through
// ListInputs), and the split of a manifest into Slurm job-array shards.
//
// Format (text, one recording per line, sorted by path, '#' starts a comment where a field
// would start; ParseManifestLine):
//   # fogpipe-manifest-v1: <count> recordings, <total> bytes; columns: path size_bytes
//   /data/campaign/run001.h5 123456789
//   "/data/campaign/run 2 #b.h5" 123456789
// A path with whitespace, '#', '"' or '\' is written in double quotes with '"' and '\' escaped.
// Paths are absolute, so the manifest may be moved; sizes are those seen when planning.
//
// Every shard of an array job reads the same manifest and computes its own part of it from
// (shard, num_shards) alone: nothing is derived from SLURM_ARRAY_TASK_COUNT, which changes when
// only failed indices are resubmitted.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/io/inputs.h"

namespace fogpipe::io {

/// How a manifest is split into shards.
enum class ShardBy {
  /// Every num_shards-th file of the sorted list, starting at `shard` .
  kStride,
  /// Greedy longest-processing-time: files by decreasing size (ties by path) each go to the shard
  /// with the fewest bytes so far (ties: lowest index). Graham (1969) bounds the largest shard at
  /// 4/3 - 1/(3 num_shards) times the optimum; the analysis time is about linear in the size.
  kSize,
};
const char* ToString(ShardBy by);
bool ParseShardBy(const std::string& text, ShardBy* by);

/// The manifest text for `inputs` (as listed by ListInputs: sorted, unique). Paths are
/// made absolute against the current folder.
std::string FormatManifest(const std::vector<InputFile>& inputs);

/// Writes FormatManifest(inputs) to `path` through a temporary file in the same folder renamed
/// when complete. Returns false with *error when it cannot.
bool WriteManifest(const std::string& path, const std::vector<InputFile>& inputs,
                   std::string* error);

/// The inputs of shard `shard` in [0, num_shards), kept in the sorted order of `inputs`.
/// num_shards <= 1 returns everything. Depends only on the paths and sizes, so every process
/// computes the same partition; the union of all shards is `inputs`, and the shards are disjoint.
std::vector<InputFile> SelectShard(const std::vector<InputFile>& inputs, int shard, int num_shards,
                                   ShardBy by);

}  // namespace fogpipe::io
