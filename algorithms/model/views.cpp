#include "algorithms/model/views.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>

#include "algorithms/allan/allan.h"
#include "algorithms/model/deterministic_fit.h"
#include "algorithms/model/spectrum.h"

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

void ComputeAllanView(const AllanData& d, const StochasticModel& m, const ViewOptions& o,
                      double alpha_view, AllanView* v, std::vector<Failure>* failures) {
  const double c2 = o.relative_floor * o.relative_floor;
  v->tau_s = d.tau_s;
  v->avar_meas = d.avar;
  v->edf = d.edf;
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
  v->critical = BonferroniCriticalZ(static_cast<int>(v->z.size()), alpha_view);
  const std::vector<double> az = Abs(v->z);
  v->statistic = az.empty() ? 0.0 : *std::max_element(az.begin(), az.end());
  for (auto [a, b] : Runs(az, v->critical)) {
    failures->push_back({"tau", d.tau_s[a] / std::sqrt(2.0), d.tau_s[b] * std::sqrt(2.0), "",
                         std::pow(MaxAbs(az, a, b) / v->critical, 2)});
  }
}

void ComputeFrequencyView(const Eigen::VectorXd& r, double fs, const StochasticModel& m,
                          const ViewOptions& o, double alpha_view, FrequencyView* v,
                          std::vector<Failure>* failures) {
  // Display: Welch PSD and the model PSD (scaled like the line test below).
  long seg = 64;
  while (seg * 2 <= r.size() / o.welch_segments) seg *= 2;
  const Spectrum w = WelchPsd(r, fs, static_cast<int>(seg));
  v->dof = w.dof;
  // Line test: the periodogram (2x zero padded) over the model PSD. Each unpadded bin of a
  // periodogram of Gaussian noise is S(f) Exp(1) (chi2(2)/2), so P(ratio > x) = exp(-x) exactly;
  // a line of amplitude W adds n W^2 / (4 sigma^2) to the ratio (Rife & Boorstyn 1974).
  const Spectrum p = Periodogram(r, fs, 2);
  const double record = r.size() / fs;
  std::vector<double> ratio, freq;
  for (size_t k = 1; k + 1 < p.psd.size(); ++k) {
    if (p.frequency_hz[k] * record < o.min_line_cycles) continue;
    const double mp = ModelOneSidedPsd(m, p.frequency_hz[k], fs);
    freq.push_back(p.frequency_hz[k]);
    ratio.push_back(mp > 0 ? p.psd[k] / mp : 0.0);
  }
  if (ratio.empty()) return;
  std::vector<double> sorted = ratio;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  // Only the shape of the model PSD is tested here (its level is the Allan view's business):
  // scale it so the median ratio is the median of Exp(1), ln 2.
  v->scale = sorted[sorted.size() / 2] / std::log(2.0);
  if (!(v->scale > 0)) v->scale = 1.0;
  for (int k = std::max(1, o.psd_skip_bins); k + 1 < static_cast<int>(w.psd.size()); ++k) {
    v->frequency_hz.push_back(w.frequency_hz[k]);
    v->psd.push_back(w.psd[k]);
    v->model_psd.push_back(v->scale * ModelOneSidedPsd(m, w.frequency_hz[k], fs));
  }
  std::vector<double> z(ratio.size());
  for (size_t i = 0; i < ratio.size(); ++i) z[i] = UpperTailZ(std::exp(-ratio[i] / v->scale));
  // The padded grid has two points per independent Fourier bin.
  v->critical =
      BonferroniCriticalZOneSided(std::max(1, static_cast<int>(z.size() / 2)), alpha_view);
  v->statistic = *std::max_element(z.begin(), z.end());
  const double df = p.frequency_hz[1];
  for (auto [a, b] : Runs(z, v->critical)) {
    int peak = a;
    for (int i = a; i <= b; ++i)
      if (z[i] > z[peak]) peak = i;
    v->line_frequency_hz.push_back(freq[peak]);
    v->line_z.push_back(z[peak]);
    failures->push_back(
        {"frequency", freq[a] - df, freq[b] + df, "", std::pow(z[peak] / v->critical, 2)});
  }
}

void ComputeTimeView(const Eigen::VectorXd& r, double fs, const StochasticModel& m,
                     const ViewOptions& o, double alpha_view, TimeView* v,
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
  for (long l = len; l <= 8 * len && 2 * l <= n; l *= 2) {
    const double sd = std::sqrt(2.0 * ModelAllanVariance(m, l / fs));
    for (long b = l; b + l <= n; b += std::max(1L, l / 2)) {
      const double before = (c[b] - c[b - l]) / l, after = (c[b + l] - c[b]) / l;
      v->boundary_s.push_back(b / fs);
      v->boundary_window_s.push_back(l / fs);
      v->z_mean.push_back(sd > 0 ? (after - before) / sd : 0.0);
    }
  }
  const int count = static_cast<int>(v->z_mean.size() + v->z_variance.size());
  v->critical = BonferroniCriticalZ(count, alpha_view);
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
    failures->push_back({"time", x.from, x.to, "", std::pow(x.peak_z / v->critical, 2)});
  }
  for (auto [a, b] : Runs(av, v->critical)) {
    failures->push_back({"time", v->center_s[a] - 0.5 * v->window_s,
                         v->center_s[b] + 0.5 * v->window_s, "",
                         std::pow(MaxAbs(av, a, b) / v->critical, 2)});
  }
}

std::vector<std::complex<double>> Dft(const Eigen::VectorXd& x) {
  std::vector<double> in(x.size());
  const double mean = x.mean();
  for (long i = 0; i < x.size(); ++i) in[i] = x[i] - mean;
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> out;
  fft.fwd(out, in);
  return out;
}

// Score (Lagrange multiplier) test of "rate += c * x(t)" under the stochastic model, in the
// frequency domain (Whittle 1953): with R_k the DFT of the residual and X_k that of the regressor,
// E|R_k|^2 = w_k = n fs S(f_k) / 2 (S one-sided), U = sum_k Re(R_k conj X_k) / w_k has variance
// sum_k |X_k|^2 / (2 w_k), and z = U / sd(U) ~ N(0, 1). This is the generalised least-squares
// t-statistic of c with the noise covariance of the fitted model: coloured noise (bias
// instability, rate random walk) is down-weighted where the model says it is strong.
double WhittleScoreZ(const std::vector<std::complex<double>>& r_dft,
                     const std::vector<std::complex<double>>& xd, const std::vector<double>& w) {
  double u = 0, var = 0;
  for (size_t k = 1; k < w.size(); ++k) {
    if (!(w[k] > 0)) continue;
    u += (r_dft[k] * std::conj(xd[k])).real() / w[k];
    var += std::norm(xd[k]) / (2.0 * w[k]);
  }
  return var > 0 ? u / std::sqrt(var) : 0.0;
}

void ComputeAuxView(const Eigen::VectorXd& r, double fs, const std::vector<PreparedAux>& aux,
                    const StochasticModel& m, const ViewOptions& o, double alpha_view, AuxView* v,
                    std::vector<Failure>* failures) {
  const long block = std::max(1L, static_cast<long>(std::lround(o.aux_block_s * fs)));
  const Eigen::VectorXd rl = BlockMeans(r, block);
  if (rl.size() < 8) return;
  for (long b = 0; b < rl.size(); ++b) {
    v->block_center_s.push_back((b * block + 0.5 * block) / fs);
    v->residual_lowpass.push_back(rl[b]);
  }
  const long n = r.size();
  const std::vector<std::complex<double>> r_dft = Dft(r);
  std::vector<double> w(n / 2, 0.0);  // bins 1 .. n/2 - 1 (no mean, no Nyquist)
  for (long k = 1; k < n / 2; ++k) w[k] = n * fs * ModelOneSidedPsd(m, fs * k / n, fs) / 2.0;
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
    cv.z = WhittleScoreZ(r_dft, pa.dft, w);
    cv.z_derivative = WhittleScoreZ(r_dft, pa.dft_derivative, w);
    v->channels.push_back(cv);
  }
  v->critical = BonferroniCriticalZ(2 * static_cast<int>(std::max<size_t>(v->channels.size(), 1)),
                                    alpha_view);
  for (const auto& cv : v->channels) {
    v->statistic = std::max({v->statistic, std::abs(cv.z), std::abs(cv.z_derivative)});
    const double nan = std::nan("");
    if (std::abs(cv.z) > v->critical)
      failures->push_back({"aux", nan, nan, cv.name, std::pow(cv.z / v->critical, 2)});
    if (std::abs(cv.z_derivative) > v->critical)
      failures->push_back(
          {"aux", nan, nan, "d(" + cv.name + ")/dt", std::pow(cv.z_derivative / v->critical, 2)});
  }
}

}  // namespace

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
    d.ci_low.push_back(t.ci_low[i]);
    d.ci_high.push_back(t.ci_high[i]);
  }
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
    p.dft = Dft(ch.values);
    p.dft_derivative = Dft(p.derivative);
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
  ComputeAllanView(allan, m, o, av, &v.allan, &v.failures);
  ComputeFrequencyView(r, fs, m, o, av, &v.frequency, &v.failures);
  ComputeTimeView(r, fs, m, o, av, &v.time, &v.failures);
  if (has_aux) ComputeAuxView(r, fs, aux, m, o, av, &v.aux, &v.failures);
  auto sq = [](double x) { return x * x; };
  v.error = std::max({sq(v.allan.statistic / v.allan.critical),
                      sq(v.frequency.statistic / v.frequency.critical),
                      sq(v.time.statistic / v.time.critical),
                      has_aux ? sq(v.aux.statistic / v.aux.critical) : 0.0});
  v.consistent = v.error <= 1.0;
  return v;
}

}  // namespace fogpipe::model
