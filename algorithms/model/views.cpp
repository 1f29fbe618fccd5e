#include "algorithms/model/views.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>

#include "algorithms/allan/allan.h"
#include "algorithms/model/deterministic_fit.h"
#include "algorithms/model/spectrum.h"
#include "algorithms/model/targeted_tests.h"

namespace fogpipe::model {
namespace {

Eigen::VectorXd PrefixSum(const Eigen::VectorXd& x) {
  Eigen::VectorXd c(x.size() + 1);
  c[0] = 0;
  for (long i = 0; i < x.size(); ++i) c[i + 1] = c[i] + x[i];
  return c;
}

// Runs of consecutive indices with value > limit: [first, last] pairs.
std::vector<std::pair<int, int>> Runs(const std::vector<double>& v, double limit) {
  std::vector<std::pair<int, int>> runs;
  int start = -1;
  for (int i = 0; i <= static_cast<int>(v.size()); ++i) {
    const bool in = i < static_cast<int>(v.size()) && v[i] > limit;
    if (in && start < 0) start = i;
    if (!in && start >= 0) {
      runs.emplace_back(start, i - 1);
      start = -1;
    }
  }
  return runs;
}

// The targeted scans of the time view and the aux score run on at most this many (block-mean)
// samples.
constexpr long kScanSamples = 1L << 18;

long ScanBlock(long n) { return std::max(1L, (n + kScanSamples - 1) / kScanSamples); }

// The residual as the time view's targeted scans and the aux score see it: on long records the
// means of blocks of B = ceil(n / kScanSamples) samples (a trailing partial block is dropped), so
// that their DFTs cost O(kScanSamples log kScanSamples) instead of O(n log n) per evaluation. A
// step or a warm-up of at least 5 s, and a temperature cycle of minutes to hours, are unchanged
// by averaging over B / fs <= 1 s (24 h at 100 Hz: B = 33, 0.33 s).
struct Decimated {
  long block = 1;
  double sample_rate_hz = 0;
  Eigen::VectorXd x;
  std::vector<std::complex<double>> dft;  // MeanRemovedDft(x)
};

Decimated Decimate(const Eigen::VectorXd& r, double fs) {
  Decimated d;
  d.block = ScanBlock(r.size());
  d.sample_rate_hz = fs / static_cast<double>(d.block);
  d.x = d.block > 1 ? BlockMeans(r, d.block) : r;
  d.dft = MeanRemovedDft(d.x);
  return d;
}

// Boundaries whose leave-window-out reference has fewer degrees of freedom are not tested.
constexpr double kMinDof = 8.0;

double MaxAbs(const std::vector<double>& v, int a, int b) {
  double m = 0;
  for (int i = a; i <= b; ++i) m = std::max(m, std::abs(v[i]));
  return m;
}

std::vector<double> Abs(const std::vector<double>& v) {
  std::vector<double> a(v.size());
  for (size_t i = 0; i < v.size(); ++i) a[i] = std::abs(v[i]);
  return a;
}

void ComputeAllanView(const AllanData& d, const StochasticModel& m, const ViewOptions& o, double fs,
                      double record_s, double alpha_view, AllanView* v,
                      std::vector<Failure>* failures) {
  const double c2 = o.relative_floor * o.relative_floor;
  v->tau_s = d.tau_s;
  v->avar_meas = d.avar;
  v->edf = d.edf;
  v->alpha = d.alpha;
  v->alpha_method = d.alpha_method;
  v->ci_low = d.ci_low;
  v->ci_high = d.ci_high;
  for (Term t : m.terms) {
    v->term_names.push_back(ToString(t));
    std::vector<double> curve;
    for (double tau : d.tau_s) curve.push_back(TermAllanVariance(m, t, tau));
    v->term_avar.push_back(curve);
  }
  for (size_t j = 0; j < d.tau_s.size(); ++j) {
    const double model = ModelAllanVariance(m, d.tau_s[j]);
    v->avar_model.push_back(model);
    const double edf = std::isfinite(d.edf[j]) && d.edf[j] > 0 ? d.edf[j] : 1.0;
    const double nu = 2.0 / (2.0 / edf + c2);
    v->z.push_back(model > 0 ? WilsonHilfertyZ(d.avar[j] / model, nu) : 0.0);
  }
  // alpha_view is split between the per-tau tests and the Gauss-Markov bump test.
  v->critical = BonferroniCriticalZ(static_cast<int>(v->z.size()), 0.5 * alpha_view);
  const std::vector<double> az = Abs(v->z);
  v->statistic = az.empty() ? 0.0 : *std::max_element(az.begin(), az.end());
  for (auto [a, b] : Runs(az, v->critical)) {
    failures->push_back({ViewDomain::kTau, d.tau_s[a] / std::sqrt(2.0), d.tau_s[b] * std::sqrt(2.0),
                         "", std::pow(MaxAbs(az, a, b) / v->critical, 2)});
  }
  const TargetedTest gm = ScanGaussMarkov(d, fs, record_s, m, o, 0.5 * alpha_view);
  if (!gm.evaluated) return;
  v->gm_z = gm.z;
  v->gm_critical = gm.critical;
  v->gm_correlation_time_s = gm.location;
  v->gm_sigma_rad_s = gm.size;
  v->statistic = std::max(v->statistic, gm.z * v->critical / gm.critical);
  if (gm.z > gm.critical)
    failures->push_back({ViewDomain::kTau, gm.from, gm.to, "", std::pow(gm.z / gm.critical, 2)});
}

void ComputeFrequencyView(const Eigen::VectorXd& r, double fs, const StochasticModel& m,
                          const ViewOptions& o, double alpha_view, FrequencyView* v,
                          std::vector<Failure>* failures) {
  // One Welch PSD (Welch 1967) is both displayed and tested: Hann segments of the largest fast
  // FFT size <= n / welch_segments, 50 % overlap. Under the model each bin is S(f) chi2(nu)/nu
  // with Welch's equivalent dof nu (Percival & Walden 1993, sec. 6.17), so the ratio psd / model
  // gives a one-sided Wilson-Hilferty z. Segments of ~1 M samples keep every FFT in cache: on
  // 24 h at 100 Hz this costs ~0.5 s of CPU against 1.3 s for the 2x zero-padded periodogram (and
  // 8.6e6 bins of per-bin work it replaced). Sensitivity:
  // a line of amplitude W adds L W^2 / (6 sigma^2) to the ratio of its bin (Hann, white noise of
  // variance sigma^2, L samples per segment), averaged over K ~ 2 n / L segments. At n / L = 8
  // (K = 15, nu = 28.5) on 24 h at 100 Hz the bin is flagged at ratio 3.2 (z_c = 5.47 over 5.4e5
  // bins), i.e. W^2 = 106 sigma^2 / n, against 75 sigma^2 / n for the 2x padded periodogram
  // (ratio 19.7 over 4.3e6 bins): 1.4x the power, 1.2x the amplitude.
  const long seg = FastFftSizeAtMost(std::max(1L, static_cast<long>(r.size()) / o.welch_segments));
  if (seg < 64) return;
  const Spectrum w = WelchPsd(r, fs, static_cast<int>(seg));
  if (w.psd.size() < 3) return;
  v->dof = w.dof;
  const double record = r.size() / fs;
  std::vector<double> ratio, model_psd;
  for (int k = std::max(1, o.psd_skip_bins); k + 1 < static_cast<int>(w.psd.size()); ++k) {
    if (w.frequency_hz[k] * record < o.min_line_cycles) continue;
    const double mp = ModelOneSidedPsd(m, w.frequency_hz[k], fs);
    v->frequency_hz.push_back(w.frequency_hz[k]);
    v->psd.push_back(w.psd[k]);
    model_psd.push_back(mp);
    ratio.push_back(mp > 0 ? w.psd[k] / mp : 0.0);
  }
  if (ratio.empty()) return;
  std::vector<double> sorted = ratio;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  // Only the shape of the model PSD is tested here (its level is the Allan view's business):
  // scale it so that the median ratio is the median of chi2(nu)/nu.
  v->scale = sorted[sorted.size() / 2] / ChiSquareMedianOverNu(w.dof);
  if (!(v->scale > 0)) v->scale = 1.0;
  v->model_psd.resize(model_psd.size());
  for (size_t i = 0; i < model_psd.size(); ++i) v->model_psd[i] = v->scale * model_psd[i];
  std::vector<double> z(ratio.size());
  for (size_t i = 0; i < ratio.size(); ++i) z[i] = WilsonHilfertyZ(ratio[i] / v->scale, w.dof);
  // Bins are tested one-sided (a line raises its bin); adjacent Hann bins are correlated, which
  // makes Bonferroni over every tested bin conservative.
  v->critical = BonferroniCriticalZOneSided(static_cast<int>(z.size()), alpha_view);
  v->statistic = *std::max_element(z.begin(), z.end());
  const double df = w.frequency_hz[1];
  const std::vector<double>& freq = v->frequency_hz;
  // Runs of failing bins, merged into bands across gaps of at most max(band_gap_bins bins,
  // band_gap_fraction f) (ViewOptions has the reason): a vibration band or a line's leakage is one
  // failure, not one per bin.
  std::vector<std::pair<int, int>> bands;
  for (auto run : Runs(z, v->critical)) {
    if (!bands.empty()) {
      const double gap = freq[run.first] - freq[bands.back().second];
      if (gap <= std::max(o.band_gap_bins * df, o.band_gap_fraction * freq[run.first])) {
        bands.back().second = run.second;
        continue;
      }
    }
    bands.push_back(run);
  }
  for (auto [a, b] : bands) {
    Failure f{ViewDomain::kFrequency, freq[a] - df, freq[b] + df, "", 0.0};
    int peak = a;
    double excess = 0, positive = 0, moment = 0, ratio = 0;
    for (int i = a; i <= b; ++i) {
      if (z[i] > z[peak]) peak = i;
      if (z[i] > v->critical) ++f.failing_bins;
      const double e = v->psd[i] - v->model_psd[i];
      excess += e * df;
      positive += std::max(e, 0.0);
      moment += std::max(e, 0.0) * freq[i];
      ratio = std::max(ratio, v->model_psd[i] > 0 ? v->psd[i] / v->model_psd[i] : 0.0);
    }
    f.severity = std::pow(z[peak] / v->critical, 2);
    f.center_hz = positive > 0 ? moment / positive : freq[peak];
    f.peak_hz = freq[peak];
    f.peak_ratio = ratio;
    f.excess_power = excess;
    v->line_frequency_hz.push_back(freq[peak]);
    v->line_z.push_back(z[peak]);
    failures->push_back(f);
  }
}

void ComputeTimeView(const Eigen::VectorXd& r, double fs, const Decimated& dec,
                     const StochasticModel& m, const ViewOptions& o, double alpha_view, TimeView* v,
                     std::vector<Failure>* failures) {
  const long n = r.size();
  const long len = std::max(16L, n / o.time_windows);
  v->window_s = len / fs;
  const Eigen::VectorXd c = PrefixSum(r);
  // Windowed mean and variance (finest scale).
  const long nw = n / len;
  std::vector<double> var;
  for (long w = 0; w < nw; ++w) {
    const auto seg = r.segment(w * len, len);
    const double mean = seg.mean();
    v->center_s.push_back((w * len + 0.5 * len) / fs);
    v->mean.push_back(mean);
    var.push_back((seg.array() - mean).square().sum() / (len - 1));
  }
  v->variance = var;
  double pooled = 0;
  for (double x : var) pooled += x;
  pooled /= std::max<size_t>(var.size(), 1);
  for (double x : var) v->z_variance.push_back(WilsonHilfertyZ(x / pooled, len - 1.0));
  // Mean changes at octave scales len, 2 len, 4 len, 8 len: a step is best seen by windows about
  // as long as the noise allows (white noise favours long windows, rate random walk short ones).
  // Reference: the mean square of the same differences elsewhere in the record (boundaries at
  // least 2 l away, whose windows do not overlap this one), not the fitted model: a step or a
  // warm-up inflates the fitted rate_random_walk / rate_ramp (K^2 = D^2 / T for a step), which
  // would cap z at sqrt(3 T / (2 l)) whatever the step size; a single event cannot inflate the
  // leave-window-out reference. Any noise with stationary increments (white, flicker, random
  // walk) gives homogeneous differences, so the reference is right whatever the noise model. The
  // ratio t is Student t with nu = m / 1.75 (m differences at half-window stride; for white
  // noise their correlations at lags l/2, l, 3l/2 are 1/4, -1/2, -1/4, so var(mean d^2) is 1.75
  // times that of m independent squares). It is judged against the Student critical value
  // t_c(nu) of the same family-wise level (Wallace 1959) and reported on the normal scale as
  // z = t c / t_c(nu), so that z / c = t / t_c: the error still grows with the energy of the
  // jump. Boundaries with nu < kMinDof are not tested.
  std::vector<double> t_mean, nu_mean;
  for (long l = len; l <= 8 * len && 2 * l <= n; l *= 2) {
    const long stride = std::max(1L, l / 2);
    std::vector<double> d, at;
    for (long b = l; b + l <= n; b += stride) {
      d.push_back((c[b + l] - c[b]) / l - (c[b] - c[b - l]) / l);
      at.push_back(static_cast<double>(b));
    }
    const long m = static_cast<long>(d.size());
    std::vector<double> sq(m + 1, 0.0);  // prefix sums of d^2
    for (long i = 0; i < m; ++i) sq[i + 1] = sq[i] + d[i] * d[i];
    const long near = (2 * l + stride - 1) / stride - 1;  // |j - i| <= near: windows overlap
    for (long i = 0; i < m; ++i) {
      const long lo = std::max(0L, i - near), hi = std::min(m - 1, i + near);
      const long others = m - (hi - lo + 1);
      const double nu = others / 1.75;
      if (nu < kMinDof) continue;
      const double ms = (sq[m] - (sq[hi + 1] - sq[lo])) / others;
      v->boundary_s.push_back(at[i] / fs);
      v->boundary_window_s.push_back(l / fs);
      t_mean.push_back(ms > 0 ? d[i] / std::sqrt(ms) : 0.0);
      nu_mean.push_back(nu);
    }
  }
  const int count = static_cast<int>(t_mean.size() + v->z_variance.size());
  v->critical = BonferroniCriticalZ(count, alpha_view);
  for (size_t i = 0; i < t_mean.size(); ++i)
    v->z_mean.push_back(t_mean[i] * v->critical / NormalToStudent(v->critical, nu_mean[i]));
  const std::vector<double> am = Abs(v->z_mean), av = Abs(v->z_variance);
  for (double x : am) v->statistic = std::max(v->statistic, x);
  for (double x : av) v->statistic = std::max(v->statistic, x);
  // Failing boundaries -> intervals [b - l, b + l], merged across scales.
  struct Interval {
    double from, to, peak_z, peak_s;
  };
  std::vector<Interval> iv;
  for (size_t i = 0; i < am.size(); ++i) {
    if (am[i] <= v->critical) continue;
    iv.push_back({std::max(0.0, v->boundary_s[i] - v->boundary_window_s[i]),
                  std::min(n / fs, v->boundary_s[i] + v->boundary_window_s[i]), am[i],
                  v->boundary_s[i]});
  }
  std::sort(iv.begin(), iv.end(), [](const auto& a, const auto& b) { return a.from < b.from; });
  std::vector<Interval> merged;
  for (const auto& x : iv) {
    if (!merged.empty() && x.from <= merged.back().to) {
      auto& mm = merged.back();
      mm.to = std::max(mm.to, x.to);
      if (x.peak_z > mm.peak_z) {
        mm.peak_z = x.peak_z;
        mm.peak_s = x.peak_s;
      }
    } else {
      merged.push_back(x);
    }
  }
  for (const auto& x : merged) {
    v->change_point_s.push_back(x.peak_s);
    failures->push_back({ViewDomain::kTime, x.from, x.to, "", std::pow(x.peak_z / v->critical, 2)});
  }
  for (auto [a, b] : Runs(av, v->critical)) {
    failures->push_back({ViewDomain::kTime, v->center_s[a] - 0.5 * v->window_s,
                         v->center_s[b] + 0.5 * v->window_s, "",
                         std::pow(MaxAbs(av, a, b) / v->critical, 2)});
  }
  // The targeted GLS scans name the effect (they rank bias_step against warmup, compare.h); they
  // are not scored: their null depends on the fitted low-frequency noise, which a 6 h record
  // determines poorly (rate random walk is often fitted at 0), while the window tests above are
  // self-normalised.
  // On long records the scans run on block means (Decimated, below); the noise model is refitted
  // on the block means themselves.
  if (!o.targeted_scans) return;
  const TargetedTest step =
      ScanBiasStep(dec.x, dec.sample_rate_hz, dec.dft, m, o, alpha_view, v->window_s);
  if (step.evaluated) {
    v->step_z = step.z;
    v->step_critical = step.critical;
    v->step_time_s = step.location;
    v->step_size_rad_s = step.size;
  }
  const TargetedTest warm = ScanWarmup(dec.x, dec.sample_rate_hz, dec.dft, m, o, alpha_view);
  if (warm.evaluated) {
    v->warmup_z = warm.z;
    v->warmup_critical = warm.critical;
    v->warmup_time_constant_s = warm.location;
    v->warmup_amplitude_rad_s = warm.size;
  }
}

void ComputeAuxView(const Eigen::VectorXd& r, double fs, const Decimated& dec,
                    const std::vector<PreparedAux>& aux, const StochasticModel& m,
                    const ViewOptions& o, double alpha_view, AuxView* v,
                    std::vector<Failure>* failures) {
  const long block = std::max(1L, static_cast<long>(std::lround(o.aux_block_s * fs)));
  const Eigen::VectorXd rl = BlockMeans(r, block);
  if (rl.size() < 8) return;
  for (long b = 0; b < rl.size(); ++b) {
    v->block_center_s.push_back((b * block + 0.5 * block) / fs);
    v->residual_lowpass.push_back(rl[b]);
  }
  // The score test runs on the block means (all samples when block = 1) under the noise model
  // refitted on them: the channels' DFTs (PrepareAux) are of their block means over the same
  // blocks.
  const StochasticModel md = dec.block > 1 ? RefitNoise(dec.x, dec.sample_rate_hz, m, o) : m;
  const std::vector<double> w = WhittleWeights(md, dec.x.size(), dec.sample_rate_hz);
  for (const PreparedAux& pa : aux) {
    const AuxChannel& ch = *pa.channel;
    AuxChannelView cv;
    cv.name = ch.name;
    cv.units = ch.units;
    const Eigen::VectorXd cl = BlockMeans(ch.values, block), dl = BlockMeans(pa.derivative, block);
    cv.lowpass.assign(cl.data(), cl.data() + cl.size());
    double ne = 0;
    CorrelationWithEffectiveDof(rl, cl, &cv.r, &ne);
    CorrelationWithEffectiveDof(rl, dl, &cv.r_derivative, &ne);
    cv.z = WhittleScoreZ(dec.dft, pa.dft, w);
    cv.z_derivative = WhittleScoreZ(dec.dft, pa.dft_derivative, w);
    v->channels.push_back(cv);
  }
  v->critical = BonferroniCriticalZ(2 * static_cast<int>(std::max<size_t>(v->channels.size(), 1)),
                                    alpha_view);
  for (const auto& cv : v->channels) {
    v->statistic = std::max({v->statistic, std::abs(cv.z), std::abs(cv.z_derivative)});
    const double nan = std::nan("");
    if (std::abs(cv.z) > v->critical)
      failures->push_back({ViewDomain::kAux, nan, nan, cv.name, std::pow(cv.z / v->critical, 2)});
    if (std::abs(cv.z_derivative) > v->critical)
      failures->push_back({ViewDomain::kAux, nan, nan, "d(" + cv.name + ")/dt",
                           std::pow(cv.z_derivative / v->critical, 2)});
  }
}

}  // namespace

const char* ToString(ViewDomain domain) {
  switch (domain) {
    case ViewDomain::kTau:
      return "tau";
    case ViewDomain::kFrequency:
      return "frequency";
    case ViewDomain::kTime:
      return "time";
    case ViewDomain::kAux:
      return "aux";
  }
  return "tau";
}

std::optional<ViewDomain> ParseViewDomain(std::string_view text) {
  for (ViewDomain domain :
       {ViewDomain::kTau, ViewDomain::kFrequency, ViewDomain::kTime, ViewDomain::kAux})
    if (text == ToString(domain)) return domain;
  return std::nullopt;
}

bool ViewOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (!(alpha > 0 && alpha < 1)) return fail("alpha must be in (0, 1)");
  if (!(relative_floor >= 0 && relative_floor < 1)) return fail("relative_floor in [0, 1)");
  if (!(max_tau_fraction > 0 && max_tau_fraction <= 0.5))
    return fail("max_tau_fraction in (0, 0.5]");
  if (welch_segments < 1 || psd_skip_bins < 1 || time_windows < 4)
    return fail("welch_segments >= 1, psd_skip_bins >= 1, time_windows >= 4");
  if (band_gap_bins < 0 || !(band_gap_fraction >= 0 && band_gap_fraction < 1))
    return fail("band_gap_bins >= 0, band_gap_fraction in [0, 1)");
  if (!(aux_block_s > 0 && aux_smoothing_s >= 0))
    return fail("aux_block_s > 0, aux_smoothing_s >= 0");
  return true;
}

Eigen::VectorXd BlockMeans(const Eigen::VectorXd& x, long block) {
  const long nb = x.size() / block;
  Eigen::VectorXd m(nb);
  for (long b = 0; b < nb; ++b) m[b] = x.segment(b * block, block).mean();
  return m;
}

std::vector<long long> ViewAveragingFactors(long n, const ViewOptions& o) {
  std::vector<long long> m;
  for (long long k = 1; k <= static_cast<long long>(n * o.max_tau_fraction); k *= 2) m.push_back(k);
  return m;
}

AllanData ResidualAllan(const Eigen::VectorXd& r, double fs, const ViewOptions& o) {
  allan::AllanOptions ao;
  ao.grid.kind = allan::TauGridKind::kExplicit;
  ao.grid.explicit_m = ViewAveragingFactors(r.size(), o);
  const allan::AllanResult res = allan::ComputeAllan(r, fs, ao);
  AllanData d;
  const auto& t = res.table;
  for (size_t i = 0; i < t.size(); ++i) {
    d.tau_s.push_back(t.tau_s[i]);
    d.avar.push_back(t.sigma[i] * t.sigma[i]);
    d.edf.push_back(t.edf[i]);
    d.alpha.push_back(t.alpha[i]);
    d.alpha_method.push_back(allan::ToString(t.alpha_method[i]));
    d.ci_low.push_back(t.ci_low[i]);
    d.ci_high.push_back(t.ci_high[i]);
  }
  d.table = t;
  return d;
}

void CorrelationWithEffectiveDof(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double* r,
                                 double* n_eff) {
  const long n = a.size();
  const Eigen::VectorXd x = a.array() - a.mean(), y = b.array() - b.mean();
  const double sxx = x.squaredNorm(), syy = y.squaredNorm();
  *r = (sxx > 0 && syy > 0) ? x.dot(y) / std::sqrt(sxx * syy) : 0.0;
  // Bretherton et al. (1999) eq. 31: n_eff = n / (1 + 2 sum_k (1 - k/n) rho_x(k) rho_y(k)).
  double sum = 0;
  const long kmax = n / 5;
  for (long k = 1; k <= kmax && sxx > 0 && syy > 0; ++k) {
    const double rx = x.head(n - k).dot(x.tail(n - k)) / sxx;
    const double ry = y.head(n - k).dot(y.tail(n - k)) / syy;
    sum += (1.0 - static_cast<double>(k) / n) * rx * ry;
  }
  *n_eff = std::clamp(n / (1.0 + 2.0 * sum), 4.0, static_cast<double>(n));
}

std::vector<PreparedAux> PrepareAux(const std::vector<AuxChannel>& aux, long n, double fs,
                                    const ViewOptions& o) {
  std::vector<PreparedAux> out;
  for (const AuxChannel& ch : aux) {
    if (ch.values.size() != n) continue;
    PreparedAux p;
    p.channel = &ch;
    p.derivative = SmoothedDerivative(ch.values, fs, o.aux_smoothing_s);
    const long block = ScanBlock(n);
    p.dft = MeanRemovedDft(block > 1 ? BlockMeans(ch.values, block) : ch.values);
    p.dft_derivative = MeanRemovedDft(block > 1 ? BlockMeans(p.derivative, block) : p.derivative);
    out.push_back(std::move(p));
  }
  return out;
}

Views ComputeViews(const Eigen::VectorXd& r, double fs, const std::vector<PreparedAux>& aux,
                   const StochasticModel& m, const AllanData& allan, const ViewOptions& o) {
  Views v;
  const bool has_aux = !aux.empty();
  const int num_views = has_aux ? 4 : 3;
  const double av = o.alpha / num_views;
  const Decimated dec = Decimate(r, fs);
  ComputeAllanView(allan, m, o, fs, r.size() / fs, av, &v.allan, &v.failures);
  ComputeFrequencyView(r, fs, m, o, av, &v.frequency, &v.failures);
  ComputeTimeView(r, fs, dec, m, o, av, &v.time, &v.failures);
  if (has_aux) ComputeAuxView(r, fs, dec, aux, m, o, av, &v.aux, &v.failures);
  auto sq = [](double x) { return x * x; };
  v.view_errors = {{ViewDomain::kTau, sq(v.allan.statistic / v.allan.critical)},
                   {ViewDomain::kFrequency, sq(v.frequency.statistic / v.frequency.critical)},
                   {ViewDomain::kTime, sq(v.time.statistic / v.time.critical)}};
  if (has_aux) v.view_errors.push_back({ViewDomain::kAux, sq(v.aux.statistic / v.aux.critical)});
  v.error = 0;
  for (const ViewError& e : v.view_errors) v.error = std::max(v.error, e.error);
  v.consistent = v.error <= 1.0;
  return v;
}

double ViewErrorOf(const Views& v, ViewDomain domain) {
  for (const ViewError& e : v.view_errors)
    if (e.domain == domain) return e.error;
  return 0.0;
}

std::vector<ViewDomain> FailingViews(const Views& v) {
  std::vector<ViewDomain> out;
  for (const ViewError& e : v.view_errors)
    if (e.error > 1.0) out.push_back(e.domain);
  return out;
}

}  // namespace fogpipe::model
