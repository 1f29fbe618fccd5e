#include "algorithms/model/deterministic_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "algorithms/common/units.h"
#include "algorithms/model/spectrum.h"

namespace fogpipe::model {
namespace {

constexpr int kSandwichBlocks = 32;
constexpr long kAnchor = 1024;
constexpr double kGolden = 0.6180339887498949;

// The regressors shared by every evaluation of one record.
struct Context {
  long n = 0;
  double fs = 1.0;
  Eigen::VectorXd t;  // s
  Eigen::VectorXd temperature_centered;
  Eigen::VectorXd temperature_rate;
};

// Columns of one component at its current nonlinear parameter.
Eigen::MatrixXd Columns(const Context& ctx, Term term, double p) {
  const long n = ctx.n;
  switch (term) {
    case Term::kTemperature:
      return ctx.temperature_centered;
    case Term::kTemperatureRate:
      return ctx.temperature_rate;
    case Term::kSinusoid: {
      // Rotation recurrence, re-anchored on exact values every kAnchor samples (rounding error
      // stays ~kAnchor * eps), ~10x faster than cos/sin per sample.
      Eigen::MatrixXd c(n, 2);
      const double w = 2 * units::kPi * p;
      const std::complex<double> rot = std::polar(1.0, w / ctx.fs);
      std::complex<double> z;
      for (long i = 0; i < n; ++i) {
        z = (i % kAnchor == 0) ? std::polar(1.0, w * ctx.t[i]) : z * rot;
        c(i, 0) = z.real();
        c(i, 1) = z.imag();
      }
      return c;
    }
    case Term::kBiasStep: {
      Eigen::MatrixXd c(n, 1);
      for (long i = 0; i < n; ++i) c(i, 0) = ctx.t[i] >= p ? 1.0 : 0.0;
      return c;
    }
    case Term::kWarmup: {
      Eigen::MatrixXd c(n, 1);
      const double decay = std::exp(-1.0 / (ctx.fs * p));
      double v = 1.0;
      for (long i = 0; i < n; ++i) {
        v = (i % kAnchor == 0) ? std::exp(-ctx.t[i] / p) : v * decay;
        c(i, 0) = v;
      }
      return c;
    }
    default:
      return Eigen::MatrixXd(n, 0);
  }
}

bool HasNonlinear(Term t) {
  return t == Term::kSinusoid || t == Term::kBiasStep || t == Term::kWarmup;
}

// Solves the normal equations with Jacobi scaling (columns of very different magnitude: degC,
// degC/s, 1) so that LDLT sees a condition number of the correlation matrix, not of the units.
Eigen::VectorXd SolveScaled(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  Eigen::VectorXd d = a.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd as = d.asDiagonal() * a * d.asDiagonal();
  Eigen::VectorXd x = as.ldlt().solve(d.asDiagonal() * b);
  return d.asDiagonal() * x;
}

Eigen::MatrixXd InverseScaled(const Eigen::MatrixXd& a) {
  Eigen::VectorXd d = a.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd as = d.asDiagonal() * a * d.asDiagonal();
  Eigen::MatrixXd inv = as.ldlt().solve(Eigen::MatrixXd::Identity(a.rows(), a.cols()));
  return d.asDiagonal() * inv * d.asDiagonal();
}

// Residual sum of squares of y on [fixed | extra], with the Gram of `fixed` precomputed
// (variable projection: amplitudes profiled out, O(n p) per evaluation).
class Profiler {
 public:
  Profiler(const Eigen::MatrixXd& fixed, const Eigen::VectorXd& y)
      : fixed_(fixed),
        y_(y),
        gram_(fixed.transpose() * fixed),
        xty_(fixed.transpose() * y),
        yy_(y.squaredNorm()) {}

  double Rss(const Eigen::MatrixXd& extra) const {
    const long p = fixed_.cols(), q = extra.cols();
    Eigen::MatrixXd a(p + q, p + q);
    Eigen::VectorXd b(p + q);
    a.topLeftCorner(p, p) = gram_;
    a.topRightCorner(p, q) = fixed_.transpose() * extra;
    a.bottomLeftCorner(q, p) = a.topRightCorner(p, q).transpose();
    a.bottomRightCorner(q, q) = extra.transpose() * extra;
    b.head(p) = xty_;
    b.tail(q) = extra.transpose() * y_;
    const Eigen::VectorXd beta = SolveScaled(a, b);
    return yy_ - b.dot(beta);
  }

  Eigen::VectorXd FixedResidual() const { return y_ - fixed_ * SolveScaled(gram_, xty_); }

 private:
  const Eigen::MatrixXd& fixed_;
  const Eigen::VectorXd& y_;
  Eigen::MatrixXd gram_;
  Eigen::VectorXd xty_;
  double yy_;
};

template <typename F>
double GoldenMinimize(F f, double lo, double hi, int iterations) {
  double a = lo, b = hi;
  double x1 = b - kGolden * (b - a), x2 = a + kGolden * (b - a);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < iterations; ++i) {
    if (f1 < f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - kGolden * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + kGolden * (b - a);
      f2 = f(x2);
    }
  }
  return f1 < f2 ? x1 : x2;
}

Eigen::MatrixXd Design(const Context& ctx, const std::vector<DeterministicComponent>& comps,
                       int skip) {
  long cols = 1;
  std::vector<Eigen::MatrixXd> parts;
  for (int i = 0; i < static_cast<int>(comps.size()); ++i) {
    if (i == skip) continue;
    parts.push_back(Columns(ctx, comps[i].term, comps[i].nonlinear));
    cols += parts.back().cols();
  }
  Eigen::MatrixXd x(ctx.n, cols);
  x.col(0).setOnes();
  long c = 1;
  for (const auto& p : parts) {
    x.middleCols(c, p.cols()) = p;
    c += p.cols();
  }
  return x;
}

double SearchWarmup(const Context& ctx, const Profiler& prof, const DeterministicOptions& o) {
  const double record = ctx.n / ctx.fs;
  const double lo = std::log(std::max(o.min_warmup_tau_s, 3.0 / ctx.fs));
  const double hi = std::log(record / 3.0);
  const int grid = 24;
  int best = 0;
  double best_rss = std::numeric_limits<double>::infinity();
  for (int i = 0; i < grid; ++i) {
    const double tau = std::exp(lo + (hi - lo) * i / (grid - 1));
    const double rss = prof.Rss(Columns(ctx, Term::kWarmup, tau));
    if (rss < best_rss) {
      best_rss = rss;
      best = i;
    }
  }
  const double step = (hi - lo) / (grid - 1);
  const double a = lo + step * std::max(best - 1, 0), b = lo + step * std::min(best + 1, grid - 1);
  return std::exp(GoldenMinimize(
      [&](double lt) { return prof.Rss(Columns(ctx, Term::kWarmup, std::exp(lt))); }, a, b, 20));
}

double SearchStep(const Context& ctx, const Profiler& prof, const DeterministicOptions& o) {
  const Eigen::VectorXd r = prof.FixedResidual();
  const long n = ctx.n;
  const long k0 = std::max(1L, static_cast<long>(o.step_margin_fraction * n));
  const long k1 = std::min(n - 1, n - k0);
  double s = 0, best = -1;
  long best_k = n / 2;
  for (long k = 1; k < k1; ++k) {
    s += r[k - 1];  // sum of r[0..k-1]; a step at sample k splits [0,k) and [k,n)
    if (k < k0) continue;
    const double stat = s * s / (static_cast<double>(k) * (n - k));
    if (stat > best) {
      best = stat;
      best_k = k;
    }
  }
  return best_k / ctx.fs;
}

double SearchSinusoid(const Context& ctx, const Profiler& prof, const DeterministicOptions& o,
                      const std::vector<double>& taken_hz) {
  const Eigen::VectorXd r = prof.FixedResidual();
  const Spectrum s = Periodogram(r, ctx.fs, 2);
  const std::vector<double> bg = BandMedianBackground(s, 1.25, 33);
  const double record = ctx.n / ctx.fs;
  const double fmin = o.min_sinusoid_cycles / record;
  int best = -1;
  double best_ratio = -1;
  for (size_t k = 1; k + 1 < s.psd.size(); ++k) {
    const double f = s.frequency_hz[k];
    if (f < fmin) continue;
    bool near = false;
    for (double ft : taken_hz) near = near || std::abs(f - ft) < 2.0 / record;
    if (near || bg[k] <= 0) continue;
    const double ratio = s.psd[k] / bg[k];
    if (ratio > best_ratio) {
      best_ratio = ratio;
      best = static_cast<int>(k);
    }
  }
  if (best < 0) return fmin;
  const double df = s.frequency_hz[1];
  const double f0 = s.frequency_hz[best];
  return GoldenMinimize([&](double f) { return prof.Rss(Columns(ctx, Term::kSinusoid, f)); },
                        std::max(f0 - 1.5 * df, 0.5 * fmin), f0 + 1.5 * df, 22);
}

double RefineSinusoid(const Context& ctx, const Profiler& prof, double f0) {
  const double df = 0.5 * ctx.fs / ctx.n;
  return GoldenMinimize([&](double f) { return prof.Rss(Columns(ctx, Term::kSinusoid, f)); },
                        f0 - df, f0 + df, 14);
}

double SearchNonlinear(const Context& ctx, const Profiler& prof, const DeterministicOptions& o,
                       const DeterministicComponent& c, bool refine,
                       const std::vector<double>& taken_hz) {
  switch (c.term) {
    case Term::kWarmup:
      return SearchWarmup(ctx, prof, o);  // cheap: always the full search
    case Term::kBiasStep:
      return SearchStep(ctx, prof, o);
    case Term::kSinusoid:
      return refine ? RefineSinusoid(ctx, prof, c.nonlinear)
                    : SearchSinusoid(ctx, prof, o, taken_hz);
    default:
      return 0.0;
  }
}

// Order of initialisation: the largest, slowest effects first, so that later searches see a
// residual already cleared of them.
int InitOrder(Term t) {
  switch (t) {
    case Term::kTemperature:
      return 0;
    case Term::kTemperatureRate:
      return 1;
    case Term::kWarmup:
      return 2;
    case Term::kBiasStep:
      return 3;
    default:
      return 4;
  }
}

}  // namespace

bool DeterministicOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (!(temperature_smoothing_s >= 0)) return fail("temperature_smoothing_s must be >= 0");
  if (!(step_margin_fraction > 0 && step_margin_fraction < 0.5))
    return fail("step_margin_fraction must be in (0, 0.5)");
  if (!(min_warmup_tau_s > 0)) return fail("min_warmup_tau_s must be > 0");
  if (!(min_sinusoid_cycles >= 1)) return fail("min_sinusoid_cycles must be >= 1");
  if (refinement_passes < 0) return fail("refinement_passes must be >= 0");
  return true;
}

Eigen::VectorXd SmoothedDerivative(const Eigen::VectorXd& temp, double fs, double smoothing_s) {
  // Slope of a local least-squares line over the centred window [i - h, i + h], clipped at the
  // record ends (Savitzky & Golay 1964, first order). Unlike differencing a moving average, it
  // stays unbiased for a linear trend at the ends, where a warm-up would otherwise absorb the
  // error. Prefix sums of k, k^2, x, k x make it O(n).
  const long n = temp.size();
  if (n < 2) return Eigen::VectorXd::Zero(n);
  const long h = std::max(1L, static_cast<long>(std::lround(0.5 * smoothing_s * fs)));
  Eigen::VectorXd sk(n + 1), skk(n + 1), sx(n + 1), skx(n + 1);
  sk[0] = skk[0] = sx[0] = skx[0] = 0;
  for (long i = 0; i < n; ++i) {
    const double k = static_cast<double>(i);
    sk[i + 1] = sk[i] + k;
    skk[i + 1] = skk[i] + k * k;
    sx[i + 1] = sx[i] + temp[i];
    skx[i + 1] = skx[i] + k * temp[i];
  }
  Eigen::VectorXd d(n);
  for (long i = 0; i < n; ++i) {
    const long lo = std::max(0L, i - h), hi = std::min(n - 1, i + h);
    const double m = static_cast<double>(hi - lo + 1);
    // Centre k on i for conditioning: sums of (k - i) and (k - i)^2.
    const double ci = static_cast<double>(i);
    const double s1 = sk[hi + 1] - sk[lo], s2 = skk[hi + 1] - skk[lo];
    const double sxv = sx[hi + 1] - sx[lo], skxv = skx[hi + 1] - skx[lo];
    const double u = s1 - m * ci, uu = s2 - 2 * ci * s1 + m * ci * ci, ux = skxv - ci * sxv;
    const double den = uu - u * u / m;
    d[i] = den > 0 ? (ux - u * sxv / m) / den * fs : 0.0;
  }
  return d;
}

DeterministicFit FitDeterministic(const Eigen::VectorXd& y, double fs, const Eigen::VectorXd* temp,
                                  const std::vector<Term>& terms, const DeterministicOptions& o) {
  DeterministicFit fit;
  fit.summary.num_samples = y.size();
  std::string err;
  if (!o.IsValid(&err) || !(fs > 0)) {
    fit.summary.termination = Termination::kInvalidOptions;
    fit.summary.message = fs > 0 ? err : "sample_rate_hz must be > 0";
    return fit;
  }
  Context ctx;
  ctx.n = y.size();
  ctx.fs = fs;
  if (ctx.n < 64) {
    fit.summary.termination = Termination::kInsufficientData;
    fit.summary.message = "fewer than 64 samples";
    return fit;
  }
  ctx.t = Eigen::VectorXd::LinSpaced(ctx.n, 0.0, (ctx.n - 1) / fs);
  fit.model.temperature_smoothing_s = o.temperature_smoothing_s;

  std::vector<DeterministicComponent> comps;
  for (Term t : terms) {
    if (!IsFittedOnRate(t)) continue;
    if (NeedsTemperature(t) && (temp == nullptr || temp->size() != ctx.n)) {
      fit.summary.termination = Termination::kInsufficientData;
      fit.summary.message = std::string("term '") + ToString(t) +
                            "' needs an aux temperature channel of the rate's length";
      return fit;
    }
    DeterministicComponent c;
    c.term = t;
    comps.push_back(c);
  }
  std::stable_sort(comps.begin(), comps.end(), [](const auto& a, const auto& b) {
    return InitOrder(a.term) < InitOrder(b.term);
  });
  if (temp != nullptr && temp->size() == ctx.n) {
    fit.model.temperature_ref_degc = temp->mean();
    ctx.temperature_centered = temp->array() - fit.model.temperature_ref_degc;
    ctx.temperature_rate = SmoothedDerivative(*temp, fs, o.temperature_smoothing_s);
  }

  // Initialise the nonlinear parameters one at a time, then coordinate descent.
  const int m = static_cast<int>(comps.size());
  for (int pass = 0; pass <= o.refinement_passes; ++pass) {
    for (int i = 0; i < m; ++i) {
      if (!HasNonlinear(comps[i].term)) continue;
      // During initialisation only the components already placed enter the fixed design.
      std::vector<DeterministicComponent> placed;
      std::vector<double> taken_hz;
      for (int j = 0; j < m; ++j) {
        if (j == i) continue;
        if (pass == 0 && j > i && HasNonlinear(comps[j].term)) continue;
        placed.push_back(comps[j]);
        if (comps[j].term == Term::kSinusoid) taken_hz.push_back(comps[j].nonlinear);
      }
      const Eigen::MatrixXd fixed = Design(ctx, placed, -1);
      const Profiler prof(fixed, y);
      comps[i].nonlinear = SearchNonlinear(ctx, prof, o, comps[i], pass > 0, taken_hz);
    }
  }

  // Final joint linear solve.
  const Eigen::MatrixXd x = Design(ctx, comps, -1);
  const Eigen::MatrixXd gram = x.transpose() * x;
  const Eigen::VectorXd beta = SolveScaled(gram, x.transpose() * y);
  fit.residual = y - x * beta;
  fit.rss = fit.residual.squaredNorm();
  if (!std::isfinite(fit.rss)) {
    fit.summary.termination = Termination::kNumericalFailure;
    fit.summary.message = "non-finite residual";
    return fit;
  }

  // Linearised design for the standard errors: amplitudes plus d(model)/d(nonlinear parameter).
  std::vector<Eigen::VectorXd> jac;
  {
    long c = 1;
    for (auto& comp : comps) {
      const long q = comp.term == Term::kSinusoid ? 2 : 1;
      if (comp.term == Term::kSinusoid) {
        const double w = 2 * units::kPi * comp.nonlinear;
        const double a = beta[c], b = beta[c + 1];
        Eigen::VectorXd j(ctx.n);
        for (long i = 0; i < ctx.n; ++i)
          j[i] = 2 * units::kPi * ctx.t[i] *
                 (-a * std::sin(w * ctx.t[i]) + b * std::cos(w * ctx.t[i]));
        jac.push_back(j);
      } else if (comp.term == Term::kWarmup) {
        const double amp = beta[c], tau = comp.nonlinear;
        jac.push_back((amp / (tau * tau)) * ctx.t.array() * (-ctx.t.array() / tau).exp());
      }
      c += q;
    }
  }
  const long p = x.cols(), pj = static_cast<long>(jac.size());
  Eigen::MatrixXd xa(ctx.n, p + pj);
  xa.leftCols(p) = x;
  for (long j = 0; j < pj; ++j) xa.col(p + j) = jac[j];
  const Eigen::MatrixXd ginv = InverseScaled(xa.transpose() * xa);
  const double sigma2 = fit.rss / std::max(1.0, static_cast<double>(ctx.n - p - pj));
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(p + pj, p + pj);
  const long block = ctx.n / kSandwichBlocks;
  Eigen::VectorXd block_means(kSandwichBlocks);
  for (int b = 0; b < kSandwichBlocks; ++b) {
    const long s0 = b * block, len = (b == kSandwichBlocks - 1) ? ctx.n - s0 : block;
    const Eigen::VectorXd sb = xa.middleRows(s0, len).transpose() * fit.residual.segment(s0, len);
    meat += sb * sb.transpose();
    block_means[b] = fit.residual.segment(s0, len).mean();
  }
  const Eigen::MatrixXd cov_hac = ginv * meat * ginv;
  Eigen::VectorXd se(p + pj);
  for (long j = 0; j < p + pj; ++j) se[j] = std::sqrt(std::max(cov_hac(j, j), sigma2 * ginv(j, j)));
  const double bm_var =
      (block_means.array() - block_means.mean()).square().sum() / (kSandwichBlocks - 1);
  fit.long_run_variance_ratio = std::max(1.0, block * bm_var / std::max(sigma2, 1e-300));

  fit.model.bias_rad_s = beta[0];
  fit.model.bias_se_rad_s = se[0];
  long c = 1, cj = p;
  for (auto& comp : comps) {
    const long q = comp.term == Term::kSinusoid ? 2 : 1;
    comp.coefficients.assign(beta.data() + c, beta.data() + c + q);
    comp.coefficients_se.assign(se.data() + c, se.data() + c + q);
    if (comp.term == Term::kSinusoid || comp.term == Term::kWarmup) {
      comp.nonlinear_se = se[cj++];
    } else if (comp.term == Term::kBiasStep) {
      const double d = beta[c];
      comp.nonlinear_se = fit.long_run_variance_ratio * sigma2 / std::max(d * d, 1e-300) / fs;
    }
    c += q;
  }
  fit.model.components = comps;
  fit.summary.num_parameters =
      static_cast<int>(p + pj + std::count_if(comps.begin(), comps.end(), [](const auto& k) {
                         return k.term == Term::kBiasStep;
                       }));
  fit.summary.message = "fitted " + std::to_string(comps.size()) + " deterministic component(s)";
  return fit;
}

Eigen::VectorXd EvaluateDeterministic(const DeterministicModel& model, long n, double fs,
                                      const Eigen::VectorXd* temp, bool include_bias) {
  Context ctx;
  ctx.n = n;
  ctx.fs = fs;
  ctx.t = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / fs);
  if (temp != nullptr && temp->size() == n) {
    ctx.temperature_centered = temp->array() - model.temperature_ref_degc;
    ctx.temperature_rate = SmoothedDerivative(*temp, fs, model.temperature_smoothing_s);
  }
  Eigen::VectorXd out = Eigen::VectorXd::Constant(n, include_bias ? model.bias_rad_s : 0.0);
  for (const auto& c : model.components) {
    if (NeedsTemperature(c.term) && ctx.temperature_centered.size() != n) continue;
    const Eigen::MatrixXd cols = Columns(ctx, c.term, c.nonlinear);
    for (long j = 0; j < cols.cols() && j < static_cast<long>(c.coefficients.size()); ++j)
      out += c.coefficients[j] * cols.col(j);
  }
  return out;
}

}  // namespace fogpipe::model
