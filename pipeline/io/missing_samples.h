// Bridging of missing samples. Input contract v1: a NaN in /rate marks a missing sample.
//
// A run of at most `max_gap` NaNs between two valid samples is replaced by the straight line
// between them (linear interpolation keeps the local mean and adds no step; for the short gaps
// allowed here its effect on the Allan variance at tau >> gap is negligible, while longer gaps
// would bias it and are refused). A run touching the start or the end of the record has only one
// neighbour and takes its value. Longer runs are not bridged.
#pragma once

#include <Eigen/Core>
#include <string>

namespace fogpipe::io {

struct BridgeReport {
  long long bridged_samples = 0;     ///< NaNs replaced
  long long runs = 0;                ///< runs of consecutive NaNs found (bridged or not)
  long long longest_run = 0;         ///< samples in the longest run
  long long longest_run_start = -1;  ///< index of its first sample (-1 if none)
  long long infinite_samples = 0;    ///< +-Inf values (never bridged: not a "missing" marker)
  long long first_infinite_index = -1;
};

/// Replaces NaN runs of length <= max_gap in place. Returns true when every NaN was bridged and
/// no +-Inf is present; otherwise `x` is left partly bridged and the report says why.
bool BridgeNanRuns(Eigen::Ref<Eigen::VectorXd> x, long long max_gap, BridgeReport* report);

}  // namespace fogpipe::io
