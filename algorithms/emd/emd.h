// Empirical mode decomposition (Huang et al. 1998, Proc. R. Soc. Lond. A 454:903-995).
//
// x = sum_i imf_i + residue. Each IMF is sifted from the remainder r = x - (IMFs so far): the upper
// and lower envelopes (cubic splines through the maxima and the minima, cubic_spline.h; flat runs
// count as one extremum at their centre, extrema.h; two mirrored extrema per side at the ends,
// extrema.h MirrorEnds) are averaged and the mean is subtracted, until the stop rule is met
// (stop_rules.h). IMFs are extracted until the remainder has fewer than 2 maxima or 2 minima, or
// `max_imfs` is reached; the residue comes last.
//
// Reconstruction: the residue is recomputed at the end as x - (imf_1 + imf_2 + ... + imf_K), the
// sum taken in IMF order, so that sum(imfs) + residue == x up to one rounding of each operation
// (tested to 1e-12 relative).
//
// Memory (N samples, K IMFs): the result holds K + 1 vectors of N doubles (IMFs, residue). During
// the run:
//   - the residue vector is the running remainder r (no separate buffer);
//   - each IMF is sifted in place in its own result vector (no separate h);
//   - the envelope knots: per interior extremum one int32 position and one double moment (the
//     knot values are read from the signal, extrema.h), plus one double of Thomas work array per
//     knot of the larger envelope, shared by both solves. With E maxima and E minima that is
//     (12 E + 12 E + 8 E) bytes = 4 E doubles. White noise: E = N / 3 (0.35 N while sifting IMF 1),
//     so 1.44 N doubles with the growth slack; at most E = (N - 1) / 2, so 2 N doubles.
// So at most (K + 3) N doubles of heap, (K + 4) N with the caller's input x (plus 12 doubles of
// mirrored-knot slots in the extreme case of an extremum at every sample). With `for_each` set,
// the two splines are solved at once, each with its own work array: one more double per knot of
// the larger envelope (at most N / 2 more doubles). Tested by heap
// accounting in tests/algorithms/emd/emd_memory_test.cpp. Nothing of size N is allocated inside
// the sift loop; knot arrays grow (exactly, +1/32) only when a sift has more extrema than any
// before, and are sized down when they hold more than 8 times the extrema an IMF needs (so the
// slow IMFs at the end do not keep the first IMF's knots).
//
// Limits: N <= 2^29 samples (knot positions are int32 in half samples).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "algorithms/common/for_each.h"
#include "algorithms/common/status.h"
#include "algorithms/emd/cubic_spline.h"
#include "algorithms/emd/stop_rules.h"

namespace fogpipe::emd {

/// Options of Decompose(). The stop-rule options (stop_rule, fixed_sifts, cauchy_sd, s_number,
/// rilling_theta1/theta2/alpha, max_sifts) come from StopCriteria (stop_rules.h), where their
/// defaults are documented: 10 fixed sifts (Wu & Huang 2004/2009). The envelope defaults follow
/// MATLAB's `emd` and Rilling's emd.m.
struct EmdOptions : StopCriteria {
  /// Maximum number of IMFs; 0 = until the remainder has too few extrema.
  int max_imfs = 0;
  /// End condition of the envelope splines.
  SplineKind spline = SplineKind::kNotAKnot;
  /// Mirror two extrema per side about the ends (extrema.h MirrorEnds). If false, the envelopes
  /// pass through the interior extrema only and their end pieces are extrapolated to the ends
  /// (Huang 1998 without end treatment: larger end swings).
  bool mirror_ends = true;
  /// Runs body(i) for i in [0, n), possibly concurrently; empty (default): everything serially.
  /// The pipeline passes a tbb::parallel_for: each sift then solves the two envelope splines at
  /// once and subtracts the envelope mean in parts of at least 65536 samples
  /// (envelope.h SubtractEnvelopeMeanInParts). The IMFs are bit-identical either way (tested);
  /// with the Cauchy rule the subtraction stays serial (its sums would round differently).
  ForEach for_each;

  bool IsValid(std::string* error) const;
};

/// What one IMF is, and how it was obtained.
struct ImfInfo {
  int sifts = 0;  ///< Sifts performed.
  SiftStop stop_reason = SiftStop::kFixedCount;
  /// Mean period in samples: 2 N / (zero crossings), i.e. N over the number of full cycles (each
  /// cycle crosses zero twice); from the extrema (2 N / extrema) if it never crosses zero, and N if
  /// it has neither. Divide by the sample rate for seconds.
  double mean_period_samples = 0.0;
  double energy = 0.0;  ///< Mean square, sum imf^2 / N (signal units squared).
  int num_extrema = 0;  ///< Maxima + minima (flat runs count once).
  int num_zero_crossings = 0;
};

struct EmdSummary {
  /// kSuccess; kNoConvergence if some IMF hit max_sifts; kInsufficientData if x has fewer than 3
  /// samples or too few extrema for one IMF (then residue = x, no IMFs); kInvalidOptions;
  /// kNumericalFailure for non-finite input or an IMF that overflowed (input near the largest
  /// double); then the result is empty.
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  int num_imfs = 0;
  int total_sifts = 0;
};

struct EmdResult {
  std::vector<Eigen::VectorXd> imfs;  ///< Highest frequency first.
  Eigen::VectorXd residue;            ///< x - sum(imfs).
  std::vector<ImfInfo> imf_info;      ///< One per IMF.
  EmdSummary summary;
};

/// Decomposes x (N samples, uniformly sampled, any units) into IMFs and a residue.
EmdResult Decompose(const Eigen::Ref<const Eigen::VectorXd>& x, const EmdOptions& options);

/// Receives IMF k (0 = highest frequency) as soon as it is extracted, with its info; `imf` is
/// valid only during the call.
using ImfSink = std::function<void(int k, const Eigen::VectorXd& imf, const ImfInfo& info)>;

/// Decompose() handing each IMF to `sink` instead of keeping it: result.imfs stays empty (imf_info,
/// residue and summary are filled as by Decompose()), and the IMFs and residue are bit-identical
/// to Decompose()'s. Memory: one IMF buffer and one running sum of the IMFs instead of K IMFs, so
/// at most 5 N doubles of heap whatever K (see the header comment). An IMF that turns non-finite
/// fails the result after the sink has seen the IMFs before it.
EmdResult Decompose(const Eigen::Ref<const Eigen::VectorXd>& x, const EmdOptions& options,
                    const ImfSink& sink);

/// Decompose(*x, options, sink) for a caller that can read its input again (the streamed method
/// keeps it in a store): *x's array becomes the running remainder instead of a copy, so the input
/// is not held beside it (N doubles less). `reload(v)` must fill *v with the input as on entry;
/// it is called once at the end, where the residue needs x - sum(imfs), or after an early end.
/// On return *x holds the input again; the result is bit-identical to Decompose's. Without a sink
/// this is Decompose(*x, options, sink) and reload is not called. `reload` may throw; it then
/// propagates and *x is unspecified.
EmdResult Decompose(Eigen::VectorXd* x, const EmdOptions& options, const ImfSink& sink,
                    const std::function<void(Eigen::VectorXd*)>& reload);

/// Recomputes the shape fields of *info (mean period, energy, extrema and zero crossings, as
/// Decompose measures them) for `imf` as it now is; sifts and stop_reason are left alone. For
/// components changed after the decomposition (method/band_limit.h).
void DescribeImf(const Eigen::Ref<const Eigen::VectorXd>& imf, ImfInfo* info);

}  // namespace fogpipe::emd
