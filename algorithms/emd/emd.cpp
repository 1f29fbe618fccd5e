#include "algorithms/emd/emd.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "algorithms/emd/envelope.h"
#include "algorithms/emd/extrema.h"

namespace fogpipe::emd {

namespace {

constexpr Eigen::Index kMaxSamples = Eigen::Index{1} << 29;  // int32 half-sample positions.

// The envelope knots and the spline work array, reused for every sift of every IMF.
class EnvelopeBuffers {
 public:
  // FindExtrema storing the knots; grows the buffers (exactly, with a little slack so a sift that
  // gains a few extrema does not reallocate) and repeats the pass if the counts did not fit.
  ExtremaCounts Find(const double* x, int n, const EmdOptions& options) {
    ExtremaCounts counts = Scan(x, n, options, true);
    const bool too_small = counts.num_maxima > upper_.interior_capacity() ||
                           counts.num_minima > lower_.interior_capacity();
    // Each IMF has about half the extrema of the one before, so the knots sized for the first
    // (about 1.9 N doubles of white noise's, with the parts' scratch) would be held to the end of
    // the decomposition, where the slow IMFs need a small fraction of them: they are sized down
    // when kShrinkFactor times too large (a few times per decomposition, one more scan each).
    const int needed = std::max(counts.num_maxima, counts.num_minima);
    const bool too_large = std::max(upper_.interior_capacity(), lower_.interior_capacity()) >
                           std::int64_t{kShrinkFactor} * (needed + kMinShrinkCapacity);
    if (too_small || too_large) {
      // Interior maxima (or minima) alternate with the other kind and exclude the end samples, so
      // there are at most (n - 1) / 2 of each: the slack never takes the knots past 4 x that.
      const int most = (n - 1) / 2;
      const int keep_upper = too_large ? 0 : upper_.interior_capacity();
      const int keep_lower = too_large ? 0 : lower_.interior_capacity();
      auto grown = [most](int needed, int have) {
        return needed <= have ? have : std::max(needed, std::min(most, needed + needed / 32 + 16));
      };
      upper_.Reserve(grown(counts.num_maxima, keep_upper));
      lower_.Reserve(grown(counts.num_minima, keep_lower));
      if (too_large) scratch_ = ExtremaScratch();
      const size_t work =
          static_cast<size_t>(std::max(upper_.interior_capacity(), lower_.interior_capacity()) +
                              2 * EnvelopeKnots::kMaxMirrored);
      work_ = std::vector<double>();
      second_work_ = std::vector<double>();
      work_.resize(work);
      counts = Scan(x, n, options, true);
    }
    return counts;
  }

  // FindExtrema, in parts when the sift's envelope pass is (the same bounds on the parts).
  ExtremaCounts Scan(const double* x, int n, const EmdOptions& options, bool store) {
    const int parts = PartsForPass(n, options.for_each);
    return FindExtremaInParts(x, n, store ? &upper_ : nullptr, store ? &lower_ : nullptr, parts,
                              options.for_each, &scratch_);
  }

  // One sift of h in place (knots already found on h).
  SiftStatistics Sift(double* h, int n, const EmdOptions& options, SiftStatisticsKind kind) {
    if (options.mirror_ends) MirrorEnds(h, n, &upper_, &lower_);
    const int parts = PartsForPass(n, options.for_each);
    if (parts < 2) {
      SolveMoments(upper_, options.spline, upper_.moments(), work_.data());
      SolveMoments(lower_, options.spline, lower_.moments(), work_.data());
      return SubtractEnvelopeMean(h, n, upper_, lower_, kind, options.rilling_theta1,
                                  options.rilling_theta2);
    }
    if (second_work_.size() != work_.size()) second_work_.resize(work_.size());
    options.for_each(2, [&](int e) {
      EnvelopeKnots& knots = e == 0 ? upper_ : lower_;
      SolveMoments(knots, options.spline, knots.moments(),
                   e == 0 ? work_.data() : second_work_.data());
    });
    return SubtractEnvelopeMeanInParts(h, n, upper_, lower_, kind, options.rilling_theta1,
                                       options.rilling_theta2, parts, options.for_each);
  }

  void RebindSignal(const double* x) {
    upper_.RebindSignal(x);
    lower_.RebindSignal(x);
  }

 private:
  // Knot buffers are sized down when more than this many times the extrema (plus a floor, so
  // that short records and the last IMFs keep theirs) need.
  static constexpr int kShrinkFactor = 8;
  static constexpr int kMinShrinkCapacity = 4096;

  EnvelopeKnots upper_, lower_;
  ExtremaScratch scratch_;  // FindExtremaInParts' per-part knots
  std::vector<double> work_;
  std::vector<double> second_work_;  // the lower spline's, when both are solved at once
};

// residue = x - (imf_1 + ... + imf_K), summed in IMF order, block by block so that every array is
// read sequentially.
void RecomputeResidue(const Eigen::Ref<const Eigen::VectorXd>& x,
                      const std::vector<Eigen::VectorXd>& imfs, Eigen::VectorXd* residue) {
  constexpr Eigen::Index kBlock = 512;
  double sum[kBlock];
  const Eigen::Index n = x.size();
  for (Eigen::Index start = 0; start < n; start += kBlock) {
    const Eigen::Index len = std::min(kBlock, n - start);
    std::fill(sum, sum + len, 0.0);
    for (const Eigen::VectorXd& imf : imfs) {
      const double* p = imf.data() + start;
      for (Eigen::Index i = 0; i < len; ++i) sum[i] += p[i];
    }
    for (Eigen::Index i = 0; i < len; ++i) (*residue)[start + i] = x[start + i] - sum[i];
  }
}

double MeanPeriodSamples(int n, const ExtremaCounts& counts) {
  if (counts.num_zero_crossings > 0) return 2.0 * n / counts.num_zero_crossings;
  if (counts.num_extrema() > 0) return 2.0 * n / counts.num_extrema();
  return n;
}

}  // namespace

bool EmdOptions::IsValid(std::string* error) const {
  auto fail = [error](const char* what) {
    if (error) *error = what;
    return false;
  };
  if (fixed_sifts < 1) return fail("fixed_sifts must be >= 1");
  if (!(cauchy_sd > 0.0)) return fail("cauchy_sd must be > 0");
  if (s_number < 1) return fail("s_number must be >= 1");
  if (!(rilling_theta1 > 0.0) || !(rilling_theta2 >= rilling_theta1)) {
    return fail("rilling thresholds must satisfy 0 < theta1 <= theta2");
  }
  if (!(rilling_alpha >= 0.0 && rilling_alpha < 1.0))
    return fail("rilling_alpha must be in [0, 1)");
  if (max_sifts < 1) return fail("max_sifts must be >= 1");
  if (stop_rule == StopRule::kFixedSifts && fixed_sifts > max_sifts) {
    return fail("fixed_sifts must not exceed max_sifts");
  }
  if (max_imfs < 0) return fail("max_imfs must be >= 0 (0 = no limit)");
  return true;
}

EmdResult Decompose(const Eigen::Ref<const Eigen::VectorXd>& x, const EmdOptions& options) {
  return Decompose(x, options, ImfSink());
}

namespace {

// Decompose's steps. With `owner` (the consuming form: x views *owner, sink is set), the remainder
// takes *owner's array instead of a copy, and `reload` refills it at the end.
EmdResult DecomposeSteps(const Eigen::Ref<const Eigen::VectorXd>& x, const EmdOptions& options,
                         const ImfSink& sink, Eigen::VectorXd* owner,
                         const std::function<void(Eigen::VectorXd*)>& reload) {
  EmdResult result;
  EmdSummary& summary = result.summary;
  std::string error;
  if (!options.IsValid(&error)) {
    summary.termination = Termination::kInvalidOptions;
    summary.message = "invalid options: " + error;
    return result;
  }
  if (x.size() > kMaxSamples) {
    summary.termination = Termination::kInvalidOptions;
    summary.message = "record longer than 2^29 samples; decompose it in parts";
    return result;
  }
  if (!x.allFinite()) {
    summary.termination = Termination::kNumericalFailure;
    summary.message = "input contains NaN or Inf";
    return result;
  }
  const int n = static_cast<int>(x.size());
  // The running remainder r; ends as the residue.
  if (owner != nullptr) {
    result.residue.swap(*owner);
  } else {
    result.residue = x;
  }
  if (n < 3) {
    summary.termination = Termination::kInsufficientData;
    summary.message = "need at least 3 samples, got " + std::to_string(n);
    return result;
  }

  const StopCriteria& criteria = options;
  const SiftStatisticsKind stats_kind = StatisticsFor(options.stop_rule);
  EnvelopeBuffers buffers;
  double* r = result.residue.data();
  ExtremaCounts counts = buffers.Find(r, n, options);
  if (!counts.EnoughToSift()) {
    std::ostringstream msg;
    msg << "input has too few extrema for one IMF (" << counts.num_maxima << " maxima, "
        << counts.num_minima << " minima); residue = input";
    summary.termination = Termination::kInsufficientData;
    summary.message = msg.str();
    return result;
  }

  // With a sink, one IMF buffer is reused and the sum of the IMFs so far is kept instead of the
  // IMFs (the residue is then x - sum, as RecomputeResidue computes it: the same additions in the
  // same order).
  Eigen::VectorXd streamed_imf, imf_sum;
  if (sink) {
    streamed_imf.resize(n);
    imf_sum.setZero(n);
  } else {
    result.imfs.reserve(64);
  }
  int num_imfs = 0;
  int capped_imfs = 0;
  bool hit_max_imfs = false;
  while (counts.EnoughToSift()) {
    if (options.max_imfs > 0 && num_imfs == options.max_imfs) {
      hit_max_imfs = true;
      break;
    }
    // h_0 = r, sifted in place.
    if (sink) {
      streamed_imf = result.residue;
    } else {
      result.imfs.emplace_back(result.residue);
    }
    double* h = sink ? streamed_imf.data() : result.imfs.back().data();
    buffers.RebindSignal(h);
    SiftStopper stopper(criteria, counts);
    SiftStop reason = SiftStop::kFixedCount;
    int sifts = 0;
    while (true) {
      const SiftStatistics stats = buffers.Sift(h, n, options, stats_kind);
      ++sifts;
      // Knots are needed only if another sift may follow.
      counts =
          stopper.StopsAt(sifts) ? buffers.Scan(h, n, options, false) : buffers.Find(h, n, options);
      if (stopper.ShouldStop(sifts, counts, stats, n, &reason)) break;
      if (!counts.EnoughToSift()) {
        reason = SiftStop::kTooFewExtrema;
        break;
      }
    }
    // Report the IMF and remove it from the remainder in one pass. `probe` stays 0 unless some
    // sample is Inf or NaN (x * 0 is NaN for those), e.g. when the input is near overflow.
    double energy = 0.0, probe = 0.0;
    for (int i = 0; i < n; ++i) {
      energy += h[i] * h[i];
      probe += h[i] * 0.0;
      r[i] -= h[i];
    }
    ++num_imfs;
    if (probe != 0.0 || std::isnan(probe)) {
      const int k = num_imfs;
      result = EmdResult();
      result.summary.termination = Termination::kNumericalFailure;
      result.summary.message = "IMF " + std::to_string(k) + " became non-finite";
      return result;
    }
    ImfInfo info;
    info.sifts = sifts;
    info.stop_reason = reason;
    info.mean_period_samples = MeanPeriodSamples(n, counts);
    info.energy = energy / n;
    info.num_extrema = counts.num_extrema();
    info.num_zero_crossings = counts.num_zero_crossings;
    result.imf_info.push_back(info);
    summary.total_sifts += sifts;
    if (reason == SiftStop::kSiftCap) ++capped_imfs;
    if (sink) {
      imf_sum += streamed_imf;
      sink(num_imfs - 1, streamed_imf, info);
    }
    counts = buffers.Find(r, n, options);
  }
  if (owner != nullptr) {
    // The remainder is spent: its array takes the input again and goes back to the caller, and
    // the residue x - sum is formed in the sum's array (the same subtraction, element by element).
    streamed_imf = Eigen::VectorXd();
    reload(&result.residue);
    imf_sum = result.residue - imf_sum;
    owner->swap(result.residue);
    result.residue.swap(imf_sum);
  } else if (sink) {
    result.residue = x - imf_sum;
  } else {
    RecomputeResidue(x, result.imfs, &result.residue);
  }

  summary.num_imfs = num_imfs;
  std::ostringstream msg;
  msg << summary.num_imfs << " IMFs, " << summary.total_sifts << " sifts ("
      << ToString(options.stop_rule) << "); stopped because "
      << (hit_max_imfs ? "max_imfs was reached" : "the remainder has too few extrema");
  if (capped_imfs > 0) msg << "; " << capped_imfs << " IMF(s) hit max_sifts";
  summary.message = msg.str();
  summary.termination = capped_imfs > 0 ? Termination::kNoConvergence : Termination::kSuccess;
  return result;
}

}  // namespace

EmdResult Decompose(const Eigen::Ref<const Eigen::VectorXd>& x, const EmdOptions& options,
                    const ImfSink& sink) {
  return DecomposeSteps(x, options, sink, nullptr, nullptr);
}

EmdResult Decompose(Eigen::VectorXd* x, const EmdOptions& options, const ImfSink& sink,
                    const std::function<void(Eigen::VectorXd*)>& reload) {
  if (!sink) return Decompose(*x, options, sink);
  const Eigen::Index n = x->size();
  const Eigen::Ref<const Eigen::VectorXd> view(*x);
  EmdResult result = DecomposeSteps(view, options, sink, x, reload);
  // An early end (too few samples or extrema, a non-finite IMF) left the input in the result or
  // nowhere: the caller gets it back as on entry.
  if (x->size() != n) reload(x);
  return result;
}

void DescribeImf(const Eigen::Ref<const Eigen::VectorXd>& imf, ImfInfo* info) {
  const int n = static_cast<int>(imf.size());
  const ExtremaCounts counts = FindExtrema(imf.data(), n, nullptr, nullptr);
  info->mean_period_samples = MeanPeriodSamples(n, counts);
  info->energy = n > 0 ? imf.squaredNorm() / n : 0.0;
  info->num_extrema = counts.num_extrema();
  info->num_zero_crossings = counts.num_zero_crossings;
}

}  // namespace fogpipe::emd
