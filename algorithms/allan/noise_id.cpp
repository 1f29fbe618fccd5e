#include "algorithms/allan/noise_id.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/allan/workers.h"
#include "algorithms/common/units.h"
#include "algorithms/kernels/kernels.h"

namespace fogpipe::allan {
namespace {

using kernels::Lanes4;
using kernels::LoadColumns4;
using kernels::LoadLanes4;
using kernels::StoreLanes4;

constexpr long long kMinAcfPoints = 30;  // Riley & Greenhall 2004: the lag-1 method needs ~30.
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Sums of one series w_0..w_{L-1} for its mean-removed lag-1 autocorrelation
// r1 = sum (w_k - mu)(w_{k+1} - mu) / sum (w_k - mu)^2 (Riley & Greenhall 2004, eq. 2), expanded
// as S_lag - mu (2 S - w_0 - w_{L-1}) + (L - 1) mu^2 over S_2 - L mu^2. The series are
// differences of the mean-removed phase, so mu is at most of the order of their spread and the
// expansion loses no significant digits.
struct Lag1Sums {
  long long count = 0;
  double first = 0.0, last = 0.0, sum = 0.0, sum_sq = 0.0, sum_lag = 0.0;
  double R1() const {
    const double l = static_cast<double>(count);
    const double mu = sum / l;
    const double num = sum_lag - mu * (2.0 * sum - first - last) + (l - 1.0) * mu * mu;
    const double den = sum_sq - l * mu * mu;
    return den > 0.0 ? num / den : 0.0;
  }
};

constexpr int kMaxDifferences = 3;
constexpr long long kChunk = 4096;

// One level of a chunk in one pass: w[0, len) holds the level's series (the first `skip` values
// already counted in the previous chunk, w[skip - 1] their last), adds the new values and lag-1
// pairs to s, and writes the next level's series, next[t] = w[t + 1] - w[t], t < len - 1.
FOGPIPE_LANE_KERNEL void AddLevel(const double* w, long long len, long long skip, Lag1Sums* s,
                                  double* next) {
  if (len <= skip) return;
  if (s->count == 0) s->first = w[skip];
  // Pairs (t - 1, t) whose second element is new.
  const long long pair_begin = std::max<long long>(skip, 1);
  double sum = 0.0, sum_sq = 0.0, sum_lag = 0.0;
  long long t = 0;
  for (; t < std::min(pair_begin, len); ++t) {  // the head: no pair (or an old one) ending at t
    if (t >= skip) sum += w[t], sum_sq += w[t] * w[t];
    if (t + 1 < len) next[t] = w[t + 1] - w[t];
  }
  // The bulk, eight values at a time in two sets of vector sums (one set would wait on its own
  // additions' latency): every value is new and ends a pair, and has a successor.
  Lanes4 vsum[2] = {}, vsq[2] = {}, vlag[2] = {};
  for (; t + 8 < len; t += 8) {
    for (int u = 0; u < 2; ++u) {
      const double* wt = w + t + 4 * u;
      const Lanes4 v = LoadLanes4(wt), before = LoadLanes4(wt - 1), after = LoadLanes4(wt + 1);
      vsum[u] += v;
      vsq[u] += v * v;
      vlag[u] += before * v;
      const Lanes4 d = after - v;
      StoreLanes4(next + t + 4 * u, d);
    }
  }
  for (; t < len; ++t) {
    sum += w[t], sum_sq += w[t] * w[t], sum_lag += w[t - 1] * w[t];
    if (t + 1 < len) next[t] = w[t + 1] - w[t];
  }
  const auto total = [](const Lanes4* v) {
    const Lanes4 both = v[0] + v[1];
    return (both[0] + both[1]) + (both[2] + both[3]);
  };
  s->sum += total(vsum) + sum;
  s->sum_sq += total(vsq) + sum_sq;
  s->sum_lag += total(vlag) + sum_lag;
  s->last = w[len - 1];
  s->count += len - skip;
}

// One pass over z_k = x[(k+1)m] - x[km] (m times the k-th average), k < averages, in chunks that
// carry dmax + 1 values of history; in each chunk every difference level 0..dmax adds its new
// values and lag-1 pairs and forms the next level in one pass (two buffers, alternately).
NoiseId Lag1Method(const Eigen::VectorXd& x, long long m, long long averages, int dmax) {
  Lag1Sums sums[kMaxDifferences + 1];
  std::vector<double> buffer(static_cast<size_t>(kChunk + kMaxDifferences + 1)),
      other(buffer.size());
  const double* p = x.data();
  for (long long c0 = 0; c0 < averages; c0 += kChunk) {
    const long long c1 = std::min(c0 + kChunk, averages);
    const long long h = std::min<long long>(dmax + 1, c0);  // history before c0
    const long long len = c1 - c0 + h;
    // buffer[t] = z_{c0 - h + t}; at level j the current buffer holds w^(j)_{c0 - h + t}.
    for (long long t = 0; t < len; ++t) buffer[t] = p[(c0 - h + t + 1) * m] - p[(c0 - h + t) * m];
    double* w = buffer.data();
    double* next = other.data();
    for (int j = 0; j <= dmax; ++j) {
      const long long t_end = h - j + (c1 - c0);  // = buffer length at level j
      const long long t_begin = std::max<long long>(h - j, 0);
      if (t_end <= t_begin) break;
      AddLevel(w, t_end, t_begin, &sums[j], next);
      std::swap(w, next);
    }
  }
  NoiseId id;
  id.method = NoiseIdMethod::kLag1Autocorrelation;
  for (int d = 0; d <= dmax; ++d) {
    const double r1 = sums[d].R1();
    const double rho = r1 / (1.0 + r1);
    if (rho < 0.25 || d >= dmax) {
      id.alpha_estimate = -2.0 * (rho + d);
      id.alpha = static_cast<int>(-std::lround(2.0 * rho)) - 2 * d;
      return id;
    }
  }
  return id;
}

// Expected B1 = (N-sample variance) / (two-sample variance) of N averages for phase-noise exponent
// mu = -alpha - 1 (Howe et al. 2000, Table 3; mu = -2 covers white and flicker PM).
double ExpectedB1(double n, int mu) {
  switch (mu) {
    case 2:
      return n * (n + 1.0) / 6.0;
    case 1:
      return n / 2.0;
    case 0:
      return n * std::log(n) / (2.0 * (n - 1.0) * std::log(2.0));
    case -1:
      return 1.0;
    case -2:
      return (n * n - 1.0) / (1.5 * n * (n - 1.0));
  }
  return kNaN;
}

// Mod AVAR's window sums of m second differences D_i are third differences of block sums,
// sum_{i=j}^{j+m-1} D_i = S_{j+2m} - 2 S_{j+m} + S_j with S_k = x_k + ... + x_{k+m-1}, and the
// three block sums slide by one sample per window: four loads per window. The state at window j:
// its three block sums and the sum of the squared window sums before it.
struct ModifiedWindows {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, sum = 0.0;
};

ModifiedWindows FirstModifiedWindow(const double* x, long long m) {
  ModifiedWindows w;
  for (long long i = 0; i < m; ++i) w.s0 += x[i], w.s1 += x[i + m], w.s2 += x[i + 2 * m];
  return w;
}

// Adds the squared window sums of windows j, j + 1, ..., windows - 1 to w (at window j).
void AddModifiedWindows(const double* x, long long m, long long j, long long windows,
                        ModifiedWindows* w) {
  double s0 = w->s0, s1 = w->s1, s2 = w->s2, sum = w->sum;
  for (;; ++j) {
    kernels::AddModifiedWindow(s0, s1, s2, &sum);
    if (j + 1 >= windows) break;
    kernels::SlideModifiedWindow(x[j], x[j + m], x[j + 2 * m], x[j + 3 * m], &s0, &s1, &s2);
  }
  *w = {s0, s1, s2, sum};
}

// The windows of up to four factors (increasing, so with non-increasing window counts; each with
// at least one window) side by side, one factor per vector element: the chain of additions of one
// factor has to stay in order, and four of them side by side fill the vector units that one
// leaves idle. Every element computes exactly what AddModifiedWindows computes for its factor
// (the same kernels, algorithms/kernels/kernels.h). Four windows at a time, each stream's four
// values transposed into the four windows' vectors; a factor whose windows end takes its last
// window from AddModifiedWindows and its element then follows the first factor's streams,
// discarded.
FOGPIPE_LANE_KERNEL void AddModifiedWindowsSideBySide(const double* x, const long long* m,
                                                      int count, long long n_phase,
                                                      ModifiedWindows* out) {
  Lanes4 s0{}, s1{}, s2{}, sum{};
  const double* stream[3][4];
  long long windows[4];
  for (int k = 0; k < 4; ++k) {
    const long long mk = m[std::min(k, count - 1)];
    const ModifiedWindows first = FirstModifiedWindow(x, mk);
    s0[k] = first.s0, s1[k] = first.s1, s2[k] = first.s2;
    for (int i = 0; i < 3; ++i) stream[i][k] = x + (i + 1) * mk;
    windows[k] = n_phase - 3 * mk + 1;
  }
  const auto step = [&](Lanes4 b, Lanes4 c, Lanes4 e, double a) {
    kernels::AddModifiedWindow(s0, s1, s2, &sum);
    kernels::SlideModifiedWindow(kernels::Splat<Lanes4>(a), b, c, e, &s0, &s1, &s2);
  };
  long long j = 0;
  for (int done = count; done > 0; --done) {
    const int k_end = done - 1;  // the factor whose windows end next
    const long long last = windows[k_end] - 1;
    for (; j + 4 <= last; j += 4) {
      const std::array<Lanes4, 4> b = LoadColumns4(stream[0], j), c = LoadColumns4(stream[1], j),
                                  e = LoadColumns4(stream[2], j);
      for (int u = 0; u < 4; ++u) step(b[u], c[u], e[u], x[j + u]);
    }
    for (; j < last; ++j) {
      Lanes4 b, c, e;
      for (int k = 0; k < 4; ++k)
        b[k] = stream[0][k][j], c[k] = stream[1][k][j], e[k] = stream[2][k][j];
      step(b, c, e, x[j]);
    }
    ModifiedWindows w{s0[k_end], s1[k_end], s2[k_end], sum[k_end]};
    AddModifiedWindows(x, m[k_end], j, windows[k_end], &w);
    out[k_end] = w;
    for (int k = k_end; k < 4; ++k)
      for (int i = 0; i < 3; ++i) stream[i][k] = stream[i][0];
  }
}

// Overlapping Allan variance at factor m from the phase (tau0 units), and Mod AVAR from the sum of
// its squared window sums.
struct AllanAndModified {
  double avar = kNaN;
  double mvar = kNaN;
};

// `avar_m` > 0 is taken as the overlapping Allan variance (the caller has it); otherwise it is
// summed here. `modified` holds the windows' sums (AddModifiedWindows) where m has windows.
AllanAndModified OverlappingAllanAndModified(const Eigen::VectorXd& phase, long long m,
                                             double avar_m, const ModifiedWindows& modified) {
  AllanAndModified out;
  const long long n_phase = phase.size();
  const long long count = n_phase - 2 * m;  // second differences D_i, i < count
  const long long windows = n_phase - 3 * m + 1;
  if (count < 1 || m < 1) return out;
  const double* x = phase.data();
  const double md = static_cast<double>(m);
  if (avar_m > 0.0) {
    out.avar = avar_m;
  } else {
    double avar_sum = 0.0;
    for (long long i = 0; i < count; ++i) {
      const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
      avar_sum += d * d;
    }
    out.avar = avar_sum / (2.0 * md * md * static_cast<double>(count));
  }
  if (windows < 1) return out;
  out.mvar = modified.sum / (2.0 * md * md * md * md * static_cast<double>(windows));
  return out;
}

double RatioOf(const AllanAndModified& allan) {
  return allan.avar > 0.0 ? allan.mvar / allan.avar : kNaN;
}

// Ratio of the N-sample variance of the `averages` m-averages to the Allan variance at m
// (`allan_variance_m`; NaN: the non-overlapping two-sample variance of the same averages).
double B1Ratio(const Eigen::VectorXd& phase, long long m, long long averages,
               double allan_variance_m) {
  std::vector<double> z(static_cast<size_t>(averages));
  for (long long k = 0; k < averages; ++k) z[k] = phase[(k + 1) * m] - phase[k * m];
  const double n = static_cast<double>(z.size());
  double mu_z = 0.0;
  for (double v : z) mu_z += v;
  mu_z /= n;
  double var = 0.0;
  for (double v : z) var += (v - mu_z) * (v - mu_z);
  var /= (n - 1.0) * static_cast<double>(m) * static_cast<double>(m);  // z is m x the average
  double avar = allan_variance_m;
  if (!(avar >= 0.0)) {
    avar = 0.0;
    for (size_t k = 0; k + 1 < z.size(); ++k) avar += (z[k + 1] - z[k]) * (z[k + 1] - z[k]);
    avar /= 2.0 * (n - 1.0) * static_cast<double>(m) * static_cast<double>(m);
  }
  return avar > 0.0 ? var / avar : 1.0;
}

// Phase-noise exponent mu = -alpha - 1 of a B1 ratio whose expectations are evaluated at
// `n_expected` points: the highest mu whose boundary with mu - 1 (geometric mean of the two
// expectations) b1 exceeds, -2 (phase noise) if none. The Allan variance does not converge for
// mu = 2 (alpha = -3), so that class is Hadamard only.
int B1Class(double b1, double n_expected, int d) {
  const int mu_max = d >= 3 ? 2 : 1;
  for (int cand = mu_max; cand > -2; --cand)
    if (b1 > std::sqrt(ExpectedB1(n_expected, cand) * ExpectedB1(n_expected, cand - 1)))
      return cand;
  return -2;
}

// R(n) of flicker PM with the measurement bandwidth at the Nyquist frequency (TN 1337, A-6:
// omega_h tau = pi m).
double FlickerPmRn(long long m) {
  return 3.37 / (1.04 + 3.0 * std::log(units::kPi * static_cast<double>(m)));
}

// White (2) or flicker (1) PM from R(n): boundary at the geometric mean of 1/m and FlickerPmRn.
int PhaseNoiseAlpha(double rn, long long m) {
  const double boundary = std::sqrt(FlickerPmRn(m) / static_cast<double>(m));
  return (rn > boundary || !(rn == rn)) ? 1 : 2;
}

// Whether R(n) says frequency noise: above the geometric mean of white FM's 0.5 and flicker PM's
// R(n). Below m = 8 flicker PM's R(n) (0.39 at m = 4) comes too close to white FM's to separate
// them, and the caller keeps its other reading.
constexpr long long kMinRnFactor = 8;
bool RnSaysFrequencyNoise(double rn, long long m) { return rn > std::sqrt(0.5 * FlickerPmRn(m)); }

// R(n) along a grid, at most once per half octave of m from m = 16 on: a dense grid (every m)
// would otherwise make one O(n) pass per row, O(n^2) in all. R(n) changes slowly with m (its
// expectations move by ~ln(m) for flicker PM, 1/m for white PM, not at all for FM), far less
// than the distances between the classes it separates.
//
// The rules consult it twice (IdentifyNoiseTypes): first it records the factors they ask for and
// answers NaN (whether a rule asks at a row never depends on an R(n) value, only on the lag-1 or
// B1 reading of that row), then Compute finds all of them in shared passes and it answers those.
class RnMemo {
 public:
  explicit RnMemo(const Eigen::VectorXd& phase) : phase_(phase) {}
  double Get(long long m, double allan_variance_m) {
    const long long key =
        m < 16 ? -m : std::llround(std::floor(2.0 * std::log2(static_cast<double>(m))));
    const auto found = memo_.find(key);
    if (found != memo_.end()) return found->second;
    memo_.emplace(key, kNaN);
    asked_.push_back({m, allan_variance_m, key});
    return kNaN;
  }
  /// Computes every R(n) asked for so far (false: none was).
  bool Compute(int threads) {
    if (asked_.empty()) return false;
    std::sort(asked_.begin(), asked_.end(),
              [](const Asked& a, const Asked& b) { return a.m < b.m; });
    std::vector<long long> m;
    std::vector<double> avar;
    for (const Asked& a : asked_) m.push_back(a.m), avar.push_back(a.avar);
    const std::vector<double> rn = ModifiedToAllanRatios(phase_, m, avar, threads);
    for (size_t k = 0; k < asked_.size(); ++k) memo_[asked_[k].key] = rn[k];
    asked_.clear();
    return true;
  }

 private:
  struct Asked {
    long long m;
    double avar;
    long long key;
  };
  const Eigen::VectorXd& phase_;
  std::map<long long, double> memo_;
  std::vector<Asked> asked_;
};

// Barnes' textbook B1 with expectations at the number of averages, R(n) for phase noise.
NoiseId B1Method(const Eigen::VectorXd& phase, long long m, long long averages, int d,
                 double allan_variance_m, double n_expected, RnMemo* rn_memo = nullptr) {
  NoiseId id;
  id.method = NoiseIdMethod::kB1Ratio;
  id.alpha_estimate = kNaN;
  const int mu = B1Class(B1Ratio(phase, m, averages, allan_variance_m), n_expected, d);
  if (mu > -2) {
    id.alpha = -mu - 1;
    return id;
  }
  id.method = NoiseIdMethod::kB1AndRn;
  id.alpha = PhaseNoiseAlpha(
      rn_memo != nullptr ? rn_memo->Get(m, kNaN) : ModifiedToAllanRatio(phase, m), m);
  return id;
}

NoiseId Carried(const NoiseId& previous) {
  NoiseId id;
  id.alpha = previous.alpha;
  id.alpha_estimate = kNaN;
  id.method = NoiseIdMethod::kCarried;
  return id;
}

// Stable32's rule (see noise_id.h).
NoiseId Stable32Rule(const Eigen::VectorXd& phase, long long m, long long averages, long long count,
                     int d, const NoiseId& lag1, const NoiseId* previous, RnMemo* rn_memo) {
  if (averages >= kMinAcfPoints) return lag1;
  if (previous != nullptr && (averages < 9 || count < 9)) return Carried(*previous);
  if (averages < 4) return previous ? Carried(*previous) : NoiseId{0, kNaN, NoiseIdMethod::kNone};
  return B1Method(phase, m, averages, d, kNaN, static_cast<double>(count), rn_memo);
}

// The coverage-calibrated rule (see noise_id.h).
constexpr long long kRnConfirmBelow = 1000;  // lag-1 misreadings vanish above ~300 averages
constexpr long long kMinB1Averages = 8;
NoiseId CalibratedRule(const Eigen::VectorXd& phase, long long m, long long averages, int d,
                       double overlapping_avar, const NoiseId& lag1, const NoiseId* previous,
                       RnMemo* rn_memo) {
  NoiseId id;
  if (averages >= kMinAcfPoints) {
    id = lag1;
    if (id.alpha >= 1 && m >= kMinRnFactor) {
      const double rn = rn_memo->Get(m, overlapping_avar);
      const bool frequency = RnSaysFrequencyNoise(rn, m);
      const int alpha = frequency ? 0 : PhaseNoiseAlpha(rn, m);
      if ((!frequency || averages < kRnConfirmBelow) && alpha != id.alpha) {
        id.alpha = alpha;
        id.method = NoiseIdMethod::kLag1AndRn;
      }
    }
  } else if (averages >= kMinB1Averages || (previous == nullptr && averages >= 4)) {
    if (m < kMinRnFactor)
      return B1Method(phase, m, averages, d, overlapping_avar, static_cast<double>(averages),
                      rn_memo);
    // B1 first: random-walk FM (B1 ~ N / 2) is far from every other class and needs no O(n)
    // pass; otherwise R(n) decides between phase and frequency noise (B1's phase-noise class,
    // expectation ~0.7, overlaps white and flicker FM's, 1 and ~2, at 8-29 averages) and B1
    // orders the frequency noises.
    const int mu =
        B1Class(B1Ratio(phase, m, averages, overlapping_avar), static_cast<double>(averages), d);
    id.alpha_estimate = kNaN;
    id.method = NoiseIdMethod::kB1Ratio;
    if (mu >= 1) {
      id.alpha = -mu - 1;
    } else {
      const double rn = rn_memo->Get(m, overlapping_avar);
      id.method = NoiseIdMethod::kB1AndRn;
      id.alpha = RnSaysFrequencyNoise(rn, m) ? -std::max(mu, -1) - 1 : PhaseNoiseAlpha(rn, m);
    }
  } else {
    return previous ? Carried(*previous) : NoiseId{0, kNaN, NoiseIdMethod::kNone};
  }
  if (previous != nullptr && previous->alpha <= 0 && id.alpha >= 1) return Carried(*previous);
  return id;
}

}  // namespace

const char* ToString(NoiseIdMethod method) {
  switch (method) {
    case NoiseIdMethod::kLag1Autocorrelation:
      return "lag1";
    case NoiseIdMethod::kLag1AndRn:
      return "lag1_rn";
    case NoiseIdMethod::kB1Ratio:
      return "b1";
    case NoiseIdMethod::kB1AndRn:
      return "b1_rn";
    case NoiseIdMethod::kCarried:
      return "carried";
    case NoiseIdMethod::kNone:
      return "none";
  }
  return "none";
}

std::vector<std::string> MethodNames(const std::vector<NoiseIdMethod>& methods) {
  std::vector<std::string> names;
  names.reserve(methods.size());
  for (NoiseIdMethod m : methods) names.emplace_back(ToString(m));
  return names;
}

const char* ToString(NoiseIdRule rule) {
  return rule == NoiseIdRule::kStable32 ? "stable32" : "calibrated";
}

bool ParseNoiseIdRule(const std::string& name, NoiseIdRule* rule) {
  for (NoiseIdRule r : {NoiseIdRule::kCalibrated, NoiseIdRule::kStable32})
    if (name == ToString(r)) {
      *rule = r;
      return true;
    }
  return false;
}

double ModifiedToAllanRatio(const Eigen::VectorXd& phase, long long m, double allan_variance_m) {
  ModifiedWindows windows;
  if (m >= 1 && phase.size() - 3 * m + 1 >= 1) {
    windows = FirstModifiedWindow(phase.data(), m);
    AddModifiedWindows(phase.data(), m, 0, phase.size() - 3 * m + 1, &windows);
  }
  return RatioOf(OverlappingAllanAndModified(phase, m, allan_variance_m, windows));
}

std::vector<double> ModifiedToAllanRatios(const Eigen::VectorXd& phase,
                                          const std::vector<long long>& m,
                                          const std::vector<double>& allan_variance_m,
                                          int threads) {
  const long long n_phase = phase.size();
  std::vector<long long> with_windows;
  for (long long mk : m)
    if (mk >= 1 && n_phase - 3 * mk + 1 >= 1) with_windows.push_back(mk);
  std::vector<ModifiedWindows> windows(with_windows.size());
  const long long groups = (static_cast<long long>(with_windows.size()) + 3) / 4;
  internal::ShareAmongThreads(threads, groups, [&](long long g) {
    const int count = static_cast<int>(std::min<long long>(4, with_windows.size() - 4 * g));
    AddModifiedWindowsSideBySide(phase.data(), with_windows.data() + 4 * g, count, n_phase,
                                 windows.data() + 4 * g);
  });
  std::vector<double> rn(m.size());
  size_t next = 0;
  for (size_t k = 0; k < m.size(); ++k) {
    const bool has = next < with_windows.size() && with_windows[next] == m[k];
    rn[k] = RatioOf(OverlappingAllanAndModified(phase, m[k], allan_variance_m[k],
                                                has ? windows[next++] : ModifiedWindows()));
  }
  return rn;
}

NoiseId IdentifyNoise(const Eigen::VectorXd& phase, long long m, int d, double allan_variance_m) {
  NoiseId id;
  const long long n = phase.size() - 1;
  const long long averages = m >= 1 ? n / m : 0;
  if (averages < 4 || d < 1 || d > kMaxDifferences) {
    id.alpha_estimate = kNaN;
    return id;
  }
  id = averages >= kMinAcfPoints
           ? Lag1Method(phase, m, averages, d)
           : B1Method(phase, m, averages, d, allan_variance_m, static_cast<double>(averages));
  id.alpha = std::clamp(id.alpha, 2 - 2 * d, 2);
  return id;
}

std::vector<NoiseId> IdentifyNoiseTypes(const Eigen::VectorXd& phase,
                                        const std::vector<long long>& m,
                                        const std::vector<long long>& count,
                                        const std::vector<double>& overlapping_avar, int d,
                                        NoiseIdRule rule, int threads) {
  std::vector<NoiseId> out(m.size());
  const long long n = phase.size() - 1;
  if (d < 1 || d > kMaxDifferences) {
    for (NoiseId& id : out) id.alpha_estimate = kNaN;
    return out;
  }
  // Both rules read the lag-1 method wherever there are 30 averages.
  std::vector<NoiseId> lag1(m.size());
  internal::ShareAmongThreads(threads, static_cast<long long>(m.size()), [&](long long k) {
    const long long averages = m[k] >= 1 ? n / m[k] : 0;
    if (averages >= kMinAcfPoints) lag1[k] = Lag1Method(phase, m[k], averages, d);
  });
  RnMemo rn_memo(phase);
  for (int round = 0; round < 2; ++round) {  // RnMemo: the R(n) asked for, then their values
    if (round == 1 && !rn_memo.Compute(threads)) break;
    const NoiseId* previous = nullptr;
    for (size_t k = 0; k < m.size(); ++k) {
      const long long averages = m[k] >= 1 ? n / m[k] : 0;
      const double avar = k < overlapping_avar.size() ? overlapping_avar[k] : kNaN;
      const long long c = k < count.size() ? count[k] : averages;
      NoiseId id =
          rule == NoiseIdRule::kStable32
              ? Stable32Rule(phase, m[k], averages, c, d, lag1[k], previous, &rn_memo)
              : CalibratedRule(phase, m[k], averages, d, avar, lag1[k], previous, &rn_memo);
      id.alpha = std::clamp(id.alpha, 2 - 2 * d, 2);
      out[k] = id;
      if (id.method != NoiseIdMethod::kNone) previous = &out[k];
    }
  }
  return out;
}

}  // namespace fogpipe::allan
