// Runs of one repeated value in a recorded column: storage never written, or a stuck output.
//
// HDF5 reads every element that was never written as the dataset's fill value (0 unless the
// writer set another). Chunks that were never written are counted and refused by the reader, but
// a dataset stored as one chunk, or contiguously, and only partly filled reads back complete: its
// unwritten tail is a run of the fill value that nothing in the file's metadata reveals. A
// sensor or logger that freezes gives the same signature anywhere in the record.
//
// Real gyros repeat values too: a quantized output holds one count for several samples, and a
// ring laser gyro in lock-in outputs zero for up to half a second. Their run lengths form a
// continuous distribution with many runs near its top, so a run is judged against the record's
// own runs, not against a noise model (a first-order Markov model of repeats called the longest
// lock-in run of a real ring laser gyro a 1e-23 event). A run is flagged when it is
//   - at the end of the column, equal to the fill value, at least kMinTailRun samples and more
//     than kTailRatio times the longest other run (an unwritten tail), or
//   - anywhere, at least kMinStuckRun samples and more than kStuckRatio times the longest other
//     run (a frozen output).
// For a geometric run-length law with repeat probability q the longest of many runs exceeds the
// second longest by r samples with probability about q^r (the top order statistics' spacing of an
// exponential is Exp(1)), so a ratio of 4 at 64 samples (r >= 48) is rarer than 1e-7 even at
// q = 0.7. The tail rule is looser because it also needs the last of the record's runs to be its
// longest (probability 1 / runs) and to hold the fill value. The reported run is data, not a
// verdict: the flag says what was seen.
#pragma once

#include <Eigen/Core>
#include <string>

namespace fogpipe::io {

struct RepeatedRunReport {
  long long start = -1;        ///< index of the longest run's first sample (-1: empty column)
  long long samples = 0;       ///< its length, samples (1 when no sample repeats its predecessor)
  double value = 0.0;          ///< the repeated value, units of the column
  long long next_longest = 0;  ///< the longest run of any other value or place, samples
  bool at_end = false;         ///< the run ends at the column's last sample
  bool equals_fill_value = false;
  bool unwritten_tail = false;  ///< flagged: the end is the fill value, far longer than any run
  bool stuck = false;           ///< flagged: far longer than any other run
  bool flagged() const { return unwritten_tail || stuck; }
};

inline constexpr long long kMinTailRun = 16;
inline constexpr double kTailRatio = 2.0;
inline constexpr long long kMinStuckRun = 64;
inline constexpr double kStuckRatio = 4.0;

/// The longest run of equal consecutive samples of `x` (NaN never equals itself, so bridged
/// columns are expected) and whether it is flagged. `fill_value` is the dataset's fill value.
RepeatedRunReport FindRepeatedRun(const Eigen::Ref<const Eigen::VectorXd>& x, double fill_value);

/// One sentence for a flagged run ("" when not flagged): where (samples and seconds), which value
/// in `units`, the likely cause, and that the samples were analysed as recorded.
std::string DescribeRepeatedRun(const RepeatedRunReport& report, double sample_rate_hz,
                                const std::string& units);

}  // namespace fogpipe::io
