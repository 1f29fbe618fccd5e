#include "algorithms/model/imf_view.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/allan/edf.h"
#include "algorithms/ar/fit_ar.h"
#include "algorithms/model/spectrum.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::model {
namespace {

double Pearson(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::ArrayXd x = a.array() - a.mean(), y = b.array() - b.mean();
  const double sxx = x.square().sum(), syy = y.square().sum();
  return (sxx > 0 && syy > 0) ? (x * y).sum() / std::sqrt(sxx * syy) : 0.0;
}

// Fractional-octave moving average of a one-sided spectrum: bin j is replaced by the mean over the
// bins in [f_j 2^(-w/2), f_j 2^(w/2)] (at least bin j itself). Prefix sums: O(bins).
std::vector<double> OctaveSmooth(const std::vector<double>& p, double octaves) {
  std::vector<double> c(p.size() + 1, 0.0), out(p.size(), 0.0);
  for (size_t j = 0; j < p.size(); ++j) c[j + 1] = c[j] + p[j];
  const double half = std::pow(2.0, 0.5 * octaves);
  for (size_t j = 1; j < p.size(); ++j) {
    const size_t lo = std::max<size_t>(1, static_cast<size_t>(std::floor(j / half)));
    const size_t hi = std::min(p.size() - 1, static_cast<size_t>(std::ceil(j * half)));
    out[j] = (c[hi + 1] - c[lo]) / static_cast<double>(hi + 1 - lo);
  }
  return out;
}

// Per-IMF energies of the fitted model: `reference_realizations` simulations of the fitted
// stochastic terms at the decimated rate (fogpipe::simulation, IEEE Std 952-1997 Annex C laws,
// fixed seeds), decomposed with the same EMD options. The expectation is the mean of ln energy
// over the realizations (the test is on the log scale, so the centre is E[ln energy], not
// ln E[energy]: they differ by ~1 / nu, which matters on the slow IMFs); the spread of ln energy
// over the realizations calibrates the EDF (see ComputeImfView); the smoothed periodogram P_k of
// each reference IMF gives nu_k = 2 n (int P_k)^2 / (fs int P_k^2).
struct Reference {
  std::vector<double> energy;   // exp(mean of ln energy) over the realizations that reached k
  std::vector<double> log_var;  // sample variance of ln energy over those realizations
  std::vector<int> count;       // how many realizations reached IMF k
  std::vector<double> edf;
  std::vector<std::vector<double>> psd;  // mean smoothed periodogram of IMF k, (rad/s)^2 / Hz
  std::string error;
};

simulation::GyroErrorModel NoiseOf(const StochasticModel& m) {
  simulation::GyroErrorModel e;
  if (m.Has(Term::kWhite)) e.n_rad_sqrt_s = m.n_rad_sqrt_s;
  if (m.Has(Term::kQuantization)) e.q_rad = m.q_rad;
  if (m.Has(Term::kBiasInstability)) e.b_rad_s = m.b_rad_s;
  if (m.Has(Term::kRateRandomWalk)) e.k_rad_s_sqrt_s = m.k_rad_s_sqrt_s;
  if (m.Has(Term::kRateRamp)) e.r_rad_s2 = m.r_rad_s2;
  if (m.Has(Term::kGaussMarkov) && m.gm_sigma_rad_s > 0 && m.gm_correlation_time_s > 0)
    e.gauss_markov.push_back({m.gm_sigma_rad_s, m.gm_correlation_time_s});
  return e;
}

Reference ModelReference(long n, double fs, const StochasticModel& model, const ImfViewOptions& o) {
  Reference ref;
  std::vector<double> p1, p2;
  std::vector<std::vector<double>> logs;  // [imf][realization]
  double df = 0;
  for (int r = 0; r < o.reference_realizations; ++r) {
    simulation::GyroSimulatorOptions so;
    so.sample_rate_hz = fs;
    so.duration_s = n / fs;
    so.seed = simulation::DeriveSeed(o.reference_seed, r);
    so.errors = NoiseOf(model);
    const simulation::SimulatedRecording sim = simulation::SimulateGyro(so);
    if (!HasResult(sim.summary.termination)) {
      ref.error = sim.summary.message;
      return ref;
    }
    Eigen::VectorXd x = sim.rate_rad_s.head(std::min<long>(n, sim.rate_rad_s.size()));
    x.array() -= x.mean();
    const emd::EmdResult d = emd::Decompose(x, o.emd);
    for (size_t k = 0; k < d.imfs.size(); ++k) {
      if (logs.size() <= k) {
        logs.emplace_back();
        p1.push_back(0.0);
        p2.push_back(0.0);
        ref.psd.emplace_back();
      }
      logs[k].push_back(std::log(std::max(d.imf_info[k].energy, 1e-300)));
      const Spectrum s = Periodogram(d.imfs[k], fs, 1);
      df = s.frequency_hz.size() > 1 ? s.frequency_hz[1] : 0.0;
      const std::vector<double> sm = OctaveSmooth(s.psd, o.smoothing_octaves);
      if (ref.psd[k].empty()) ref.psd[k].assign(sm.size(), 0.0);
      for (size_t j = 1; j < sm.size(); ++j) {
        p1[k] += sm[j];
        p2[k] += sm[j] * sm[j];
        ref.psd[k][j] += sm[j];
      }
    }
  }
  // An IMF index that only some realizations reached is averaged over those that did.
  for (size_t k = 0; k < logs.size(); ++k) {
    const int c = static_cast<int>(logs[k].size());
    double mean = 0, ss = 0;
    for (double l : logs[k]) mean += l / c;
    for (double l : logs[k]) ss += (l - mean) * (l - mean);
    ref.energy.push_back(std::exp(mean));
    ref.log_var.push_back(c > 1 ? ss / (c - 1) : 0.0);
    ref.count.push_back(c);
    for (double& p : ref.psd[k]) p /= c;
    // On bins of width df: nu = 2 n (sum P df)^2 / (fs sum P^2 df) for one realization; p1, p2
    // add up c realizations, hence the division by c.
    ref.edf.push_back(p2[k] > 0 ? 2.0 * n * df * p1[k] * p1[k] / (fs * p2[k] * c) : 0.0);
  }
  return ref;
}

// EDF of the energy in the octave band of period T under the model, as the EDF of the
// overlapping Allan variance at tau = T / 2 (Greenhall & Riley 2003): an Allan variance is the
// power in an octave band around 1 / (2 tau), and Greenhall's EDF knows what the IMF spectrum does
// not: rate random walk and flicker noise are not stationary, and their band energies fluctuate far
// more than a stationary band-pass process of the same spectrum. The terms are independent, so
// nu = (sum A_i)^2 / sum (A_i^2 / nu_i) with A_i each term's Allan variance.
double AllanBandEdf(const StochasticModel& model, double period_s, double fs, long n) {
  const double tau = 0.5 * period_s;
  const long long m = std::max(1LL, std::llround(tau * fs));
  double sum = 0, weighted = 0;
  for (Term t : model.terms) {
    int alpha = 0;  // white FM
    if (t == Term::kQuantization) alpha = 2;
    if (t == Term::kBiasInstability) alpha = -1;
    if (t == Term::kRateRandomWalk || t == Term::kRateRamp) alpha = -2;  // ramp: steepest allowed
    if (t == Term::kGaussMarkov && tau < model.gm_correlation_time_s) alpha = -2;
    const double a = TermAllanVariance(model, t, m / fs);
    const double nu = allan::GreenhallEdf(alpha, 2, m, n + 1, true, true);
    if (!(a > 0) || !(nu > 0)) continue;
    sum += a;
    weighted += a * a / nu;
  }
  return weighted > 0 ? sum * sum / weighted : std::numeric_limits<double>::quiet_NaN();
}

// Variance of ln(expected energy) from the fitted parameters' standard errors, at the IMF's
// scale: each term's Allan variance at tau = T / 2 with its parameter raised by one standard error,
// relative to the model's, in quadrature (correlations ignored). At long periods this dominates:
// bias instability and rate random walk are fitted from a few long-tau Allan points.
double ParameterLogVariance(const StochasticModel& model, double period_s) {
  const double tau = 0.5 * period_s;
  const double total = ModelAllanVariance(model, tau);
  if (!(total > 0)) return 0.0;
  double v = 0;
  for (Term t : model.terms) {
    StochasticModel up = model;
    if (t == Term::kWhite) up.n_rad_sqrt_s += model.n_se;
    if (t == Term::kQuantization) up.q_rad += model.q_se;
    if (t == Term::kBiasInstability) up.b_rad_s += model.b_se;
    if (t == Term::kRateRandomWalk) up.k_rad_s_sqrt_s += model.k_se;
    if (t == Term::kRateRamp) up.r_rad_s2 += model.r_se;
    if (t == Term::kGaussMarkov) up.gm_sigma_rad_s += model.gm_sigma_se;
    const double d = (TermAllanVariance(up, t, tau) - TermAllanVariance(model, t, tau)) / total;
    v += d * d;
  }
  return v;
}

}  // namespace

bool ImfViewOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (max_samples < 64) return fail("imf.max_samples must be >= 64");
  if (reference_realizations < 1) return fail("imf.reference_realizations must be >= 1");
  if (!(smoothing_octaves >= 0)) return fail("imf.smoothing_octaves must be >= 0");
  if (!(relative_floor >= 0 && relative_floor < 1)) return fail("imf.relative_floor in [0, 1)");
  if (!(alpha > 0 && alpha < 1)) return fail("imf.alpha must be in (0, 1)");
  if (!(min_cycles > 0)) return fail("imf.min_cycles must be > 0");
  if (!(min_shared_fraction >= 0 && min_shared_fraction <= 1))
    return fail("imf.min_shared_fraction in [0, 1]");
  if (max_ar_order < 1 || max_ar_order > ar::ArOptions::kMaxOrderLimit)
    return fail("imf.max_ar_order out of range");
  return emd.IsValid(error);
}

ImfView ComputeImfView(const Eigen::VectorXd& residual, double fs,
                       const std::vector<PreparedAux>& aux, const StochasticModel& model,
                       const ImfViewOptions& o) {
  ImfView v;
  std::string err;
  if (!o.IsValid(&err) || !(fs > 0)) {
    v.summary.termination = Termination::kInvalidOptions;
    v.summary.message = fs > 0 ? err : "sample_rate_hz must be > 0";
    return v;
  }
  const long n = residual.size();
  v.decimation = std::max(1L, (n + o.max_samples - 1) / o.max_samples);
  const long m = v.decimation;
  const double fsd = fs / m;
  v.sample_rate_hz = fsd;
  Eigen::VectorXd x = BlockMeans(residual, m);
  const long nd = x.size();
  if (nd < 64) {
    v.summary.termination = Termination::kInsufficientData;
    v.summary.message = "residual too short for the IMF view";
    return v;
  }
  x.array() -= x.mean();
  const emd::EmdResult d = emd::Decompose(x, o.emd);
  if (!HasResult(d.summary.termination) || d.imfs.empty()) {
    v.summary.termination = d.imfs.empty() ? Termination::kInsufficientData : d.summary.termination;
    v.summary.message = "EMD of the residual: " + d.summary.message;
    return v;
  }
  // The EMD of the fitted noise, measured (for white noise: the dyadic law of Wu & Huang 2004).
  const Reference ref = ModelReference(nd, fsd, model, o);
  if (!ref.error.empty() || ref.energy.empty()) {
    v.summary.termination = Termination::kInsufficientData;
    v.summary.message = "no reference decomposition of the fitted noise: " + ref.error;
    return v;
  }
  const double record_s = nd / fsd;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const int k_count = static_cast<int>(d.imfs.size());
  std::vector<double> param_var(k_count, nan);
  for (int k = 0; k < k_count; ++k) {
    const emd::ImfInfo& info = d.imf_info[k];
    const double period_s = info.mean_period_samples / fsd;
    v.mean_period_s.push_back(period_s);
    v.energy.push_back(info.energy);
    const bool in_ref = k < static_cast<int>(ref.energy.size()) && ref.energy[k] > 0;
    const double expected = in_ref ? ref.energy[k] : nan;
    // The smaller of the band-pass EDF of the reference IMF and the Allan band EDF (above).
    const double nu = in_ref ? std::fmin(ref.edf[k], AllanBandEdf(model, period_s, fsd, nd)) : nan;
    v.expected_energy.push_back(expected);
    v.ratio.push_back(in_ref ? info.energy / expected : nan);
    v.edf.push_back(nu);
    const bool scored =
        expected > 0 && nu > 0 && info.energy > 0 && record_s >= o.min_cycles * period_s;
    v.scored.push_back(scored ? 1 : 0);
    param_var[k] = ParameterLogVariance(model, period_s);
    ar::ArOptions ao;
    ao.max_order = o.max_ar_order;
    const ar::ArFit fit = ar::FitAr(d.imfs[k], ao);
    const bool ok = HasResult(fit.summary.termination);
    v.ar_order.push_back(ok ? fit.model.order : 0);
    v.ar_fit_percent.push_back(ok ? fit.diagnostics.fit_one_step_percent : nan);
  }
  v.summary.num_imfs = k_count;
  for (int s : v.scored) v.summary.num_scored += s;

  // Calibration of the EDF by the reference realizations: ln energy of one realization has
  // variance lambda * 2 / nu_k. Each scored IMF that every realization reached gives an estimate
  // s_k^2 nu_k / 2 ~ lambda chi2(R - 1) / (R - 1); their plain mean has (R - 1) x (count) degrees
  // of freedom (equal weights: weighting by 2 / nu_k would let the two slowest IMFs decide).
  // lambda captures what the EDF does not: EMD's mode mixing moves energy between neighbouring
  // IMFs, so an IMF's energy scatters more than that of a fixed band-pass filter (measured on
  // effect-free navigation-grade recordings: lambda ~ 1.2-2 on every IMF).
  const int reps = o.reference_realizations;
  double lambda_sum = 0;
  int pooled = 0;
  for (int k = 0; k < k_count; ++k) {
    if (!v.scored[k] || ref.count[k] != reps || reps < 2) continue;
    lambda_sum += ref.log_var[k] * v.edf[k] / 2.0;
    ++pooled;
  }
  v.log_variance_ratio = pooled > 0 ? lambda_sum / pooled : 1.0;
  v.reference_dof = pooled > 0 ? pooled * (reps - 1.0) : std::numeric_limits<double>::infinity();

  // Energy tests: t_k = ln(energy_k / E_k) / sd_k, sd_k^2 = lambda (2 / nu_k)(1 + 1 / R) + c^2 +
  // the parameters' share; Student t with the pooled dof (the variance is estimated), one-sided.
  struct Test {
    double p;  // p-value
    int imf;
  };
  std::vector<Test> tests;
  for (int k = 0; k < k_count; ++k) {
    const double expected = v.expected_energy[k];
    const double log_sd =
        expected > 0 && v.edf[k] > 0
            ? std::sqrt(v.log_variance_ratio * 2.0 / v.edf[k] * (1.0 + 1.0 / ref.count[k]) +
                        o.relative_floor * o.relative_floor + param_var[k])
            : nan;
    v.log_sd.push_back(log_sd);
    v.z.push_back(v.scored[k] ? std::log(v.energy[k] / expected) / log_sd : nan);
    if (v.scored[k]) tests.push_back({UpperTailP(StudentToNormal(v.z[k], v.reference_dof)), k});
  }

  // Aux: Pearson r of each IMF x with each channel y (block-averaged like the residual) and with
  // its smoothed derivative, against "x is the fitted noise's IMF k, independent of y". Given y
  // and a stationary x of spectrum S_x, Var(sum x y) = int S_x |Y|^2 df, so on one-sided
  // periodogram bins r has variance 1 / n_eff, n_eff = 2 sum S_x sum P_y / sum S_x P_y, and
  // z = r sqrt(n_eff). This is Bartlett's (1935) n / sum_k rho_x(k) rho_y(k) written by Parseval
  // (Bretherton et al. 1999), and the variance of r over phase-randomised surrogates (Theiler et
  // al. 1992; Ebisuzaki 1997) of spectrum S_x: a slow IMF and a smooth 1-2 h temperature cycle
  // over 6 h share only ~10-60 independent values, far fewer than the IMF's own EDF. S_x is the
  // reference realizations' mean smoothed periodogram of IMF k, not the data IMF's own: under a
  // thermal effect the data IMF's spectrum is the temperature's, and the null variance it gives
  // would hide the effect (r ~ 0.95 with n_eff ~ 3). Two-sided. An IMF is tested against a
  // channel only where they share spectrum: at least `min_shared_fraction` of the channel's
  // variance inside the IMF's band (the bins where S_x is above a quarter of its peak). Elsewhere
  // r is carried by the far tails of S_x, which 4 realizations do not estimate and EMD end effects
  // dominate (measured: mid-period IMFs against the temperature cycle gave |z| up to 5 under the
  // null), and the test could only find an effect of the channel's spectrum where the channel has
  // none.
  auto shared_fraction = [&](const std::vector<double>& sx, const std::vector<double>& py) {
    double peak = 0, in_band = 0, total = 0;
    for (size_t j = 1; j < sx.size(); ++j) peak = std::max(peak, sx[j]);
    for (size_t j = 1; j < std::min(sx.size(), py.size()); ++j) {
      total += py[j];
      if (sx[j] >= 0.25 * peak) in_band += py[j];
    }
    return total > 0 ? in_band / total : 0.0;
  };
  auto effective_n = [&](const std::vector<double>& sx, const std::vector<double>& py) {
    double ssx = 0, spy = 0, sxy = 0;
    for (size_t j = 1; j + 1 < std::min(sx.size(), py.size()); ++j) {
      ssx += sx[j];
      spy += py[j];
      sxy += sx[j] * py[j];
    }
    return sxy > 0 ? std::min(2.0 * ssx * spy / sxy, static_cast<double>(nd)) : nan;
  };
  for (const PreparedAux& pa : aux) {
    const Eigen::VectorXd c = BlockMeans(pa.channel->values, m).head(nd);
    const Eigen::VectorXd dc = BlockMeans(pa.derivative, m).head(nd);
    const std::vector<double> pc = Periodogram(c, fsd, 1).psd, pdc = Periodogram(dc, fsd, 1).psd;
    std::vector<double> r, rd, z, zd, ne, ned;
    for (int k = 0; k < k_count; ++k) {
      r.push_back(Pearson(d.imfs[k], c));
      rd.push_back(Pearson(d.imfs[k], dc));
      const bool in_ref = v.scored[k] && k < static_cast<int>(ref.psd.size());
      // One test per (IMF, series) that shares spectrum with the IMF.
      auto add = [&](double rr, const std::vector<double>& py, std::vector<double>* zs,
                     std::vector<double>* ns) {
        double n_eff = nan, zz = nan;
        if (in_ref && shared_fraction(ref.psd[k], py) >= o.min_shared_fraction) {
          n_eff = effective_n(ref.psd[k], py);
          zz = rr * std::sqrt(n_eff);
          if (std::isfinite(zz)) tests.push_back({2.0 * UpperTailP(std::abs(zz)), k});
        }
        zs->push_back(zz);
        ns->push_back(n_eff);
      };
      add(r.back(), pc, &z, &ne);
      add(rd.back(), pdc, &zd, &ned);
    }
    v.aux_names.push_back(pa.channel->name);
    v.aux_r.push_back(r);
    v.aux_r_derivative.push_back(rd);
    v.aux_z.push_back(z);
    v.aux_z_derivative.push_back(zd);
    v.aux_n_eff.push_back(ne);
    v.aux_n_eff_derivative.push_back(ned);
  }

  // One family per record: every energy and aux test of every scored IMF, Holm's (1979) step-down
  // at `alpha` (family-wise: a correct model flags no IMF with probability >= 1 - alpha). Holm
  // rejects the r smallest p-values, p_(i) <= alpha / (m - i + 1) for i <= r; equivalently every
  // test with p <= alpha / (m - max(r, 1) + 1), the level the critical values below are quoted at.
  const int m_tests = static_cast<int>(tests.size());
  std::vector<double> sorted_p;
  for (const Test& t : tests) sorted_p.push_back(t.p);
  std::sort(sorted_p.begin(), sorted_p.end());
  int rejected = 0;
  while (rejected < m_tests && sorted_p[rejected] <= o.alpha / (m_tests - rejected)) ++rejected;
  v.test_level = o.alpha / std::max(1, m_tests - std::max(rejected, 1) + 1);
  v.critical = NormalToStudent(UpperTailZ(v.test_level), v.reference_dof);
  v.aux_critical = UpperTailZ(0.5 * v.test_level);
  v.flagged.assign(k_count, 0);
  for (const Test& t : tests)
    if (t.p <= v.test_level) v.flagged[t.imf] = 1;
  for (int f : v.flagged) v.summary.num_flagged += f;
  v.summary.message = std::to_string(v.summary.num_flagged) + " of " +
                      std::to_string(v.summary.num_scored) + " scored IMFs carry misfit";
  return v;
}

}  // namespace fogpipe::model
