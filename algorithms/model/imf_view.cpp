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
// fixed seeds), decomposed with the same EMD options. Their mean IMF energies are the
// expectation; the smoothed periodogram P_k of each reference IMF gives
// nu_k = 2 n (int P_k)^2 / (fs int P_k^2).
struct Reference {
  std::vector<double> energy, edf;
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
  std::vector<int> count;
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
      if (ref.energy.size() <= k) {
        ref.energy.push_back(0.0);
        p1.push_back(0.0);
        p2.push_back(0.0);
        count.push_back(0);
      }
      ref.energy[k] += d.imf_info[k].energy;
      const Spectrum s = Periodogram(d.imfs[k], fs, 1);
      df = s.frequency_hz.size() > 1 ? s.frequency_hz[1] : 0.0;
      const std::vector<double> sm = OctaveSmooth(s.psd, o.smoothing_octaves);
      for (size_t j = 1; j < sm.size(); ++j) {
        p1[k] += sm[j];
        p2[k] += sm[j] * sm[j];
      }
      ++count[k];
    }
  }
  // An IMF index that only some realizations reached is averaged over those that did.
  for (size_t k = 0; k < ref.energy.size(); ++k) {
    ref.energy[k] /= count[k];
    // On bins of width df: nu = 2 n (sum P df)^2 / (fs sum P^2 df).
    ref.edf.push_back(p2[k] > 0 ? 2.0 * n * df * p1[k] * p1[k] / (fs * p2[k]) : 0.0);
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
  const double reference_factor = 1.0 + 1.0 / o.reference_realizations;
  const int k_count = static_cast<int>(d.imfs.size());
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
    const double log_sd =
        expected > 0 ? std::sqrt(2.0 / nu * reference_factor + o.relative_floor * o.relative_floor +
                                 ParameterLogVariance(model, period_s))
                     : nan;
    v.log_sd.push_back(log_sd);
    v.z.push_back(scored ? std::log(info.energy / expected) / log_sd : nan);
    ar::ArOptions ao;
    ao.max_order = o.max_ar_order;
    const ar::ArFit fit = ar::FitAr(d.imfs[k], ao);
    const bool ok = HasResult(fit.summary.termination);
    v.ar_order.push_back(ok ? fit.model.order : 0);
    v.ar_fit_percent.push_back(ok ? fit.diagnostics.fit_one_step_percent : nan);
  }
  v.summary.num_imfs = k_count;
  for (int s : v.scored) v.summary.num_scored += s;
  v.critical = BonferroniCriticalZOneSided(std::max(1, v.summary.num_scored), o.alpha);
  // Aux: Fisher's z of r with the IMF's EDF as the sample size (a band-limited series of nu
  // degrees of freedom carries nu independent values), z = atanh(r) sqrt(nu - 3); two-sided
  // Bonferroni over the scored IMFs x channels x (value, derivative).
  v.aux_critical = BonferroniCriticalZ(
      std::max(1, 2 * v.summary.num_scored * static_cast<int>(aux.size())), o.alpha);
  auto fisher = [&](double r, int k) {
    const double nu = v.edf[k];
    return v.scored[k] && nu > 3
               ? std::atanh(std::clamp(r, -0.999999, 0.999999)) * std::sqrt(nu - 3)
               : nan;
  };
  for (const PreparedAux& pa : aux) {
    const Eigen::VectorXd c = BlockMeans(pa.channel->values, m).head(nd);
    const Eigen::VectorXd dc = BlockMeans(pa.derivative, m).head(nd);
    std::vector<double> r, rd, z, zd;
    for (int k = 0; k < k_count; ++k) {
      r.push_back(Pearson(d.imfs[k], c));
      rd.push_back(Pearson(d.imfs[k], dc));
      z.push_back(fisher(r.back(), k));
      zd.push_back(fisher(rd.back(), k));
    }
    v.aux_names.push_back(pa.channel->name);
    v.aux_r.push_back(r);
    v.aux_r_derivative.push_back(rd);
    v.aux_z.push_back(z);
    v.aux_z_derivative.push_back(zd);
  }
  // An IMF carries misfit when it holds more energy than the model explains, or follows an aux
  // channel (a deterministic effect the model lacks).
  for (int k = 0; k < k_count; ++k) {
    bool f = v.scored[k] && v.z[k] > v.critical;
    for (size_t c = 0; c < v.aux_names.size(); ++c)
      f = f || std::abs(v.aux_z[c][k]) > v.aux_critical ||
          std::abs(v.aux_z_derivative[c][k]) > v.aux_critical;
    v.flagged.push_back(f ? 1 : 0);
    v.summary.num_flagged += f ? 1 : 0;
  }
  v.summary.message = std::to_string(v.summary.num_flagged) + " of " +
                      std::to_string(v.summary.num_scored) + " scored IMFs carry misfit";
  return v;
}

}  // namespace fogpipe::model
