#include "algorithms/model/deterministic_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numeric>
#include <utility>

#include "algorithms/common/units.h"
#include "algorithms/model/bias_levels.h"
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
  // Aux terms: the channels (name -> values) and the smoothed derivatives of those an aux_rate
  // term reads.
  std::vector<AuxSeries> aux;
  std::vector<std::pair<std::string, Eigen::VectorXd>> aux_rate;
  // The rising/falling state of those an aux_hysteresis term reads (a channel has at most one
  // such term, so one dead band per channel).
  std::vector<std::pair<std::string, Eigen::VectorXd>> aux_state;
  double smoothing_s = 120.0;
};

const Eigen::VectorXd* AuxValues(const Context& ctx, const std::string& name) {
  for (const auto& series : ctx.aux)
    if (series.name == name && series.values && series.values->size() == ctx.n)
      return series.values;
  return nullptr;
}

// The smoothed derivative of a channel, computed once per context.
const Eigen::VectorXd& AuxRate(Context* ctx, const std::string& name) {
  for (const auto& [channel, derivative] : ctx->aux_rate)
    if (channel == name) return derivative;
  ctx->aux_rate.emplace_back(name,
                             SmoothedDerivative(*AuxValues(*ctx, name), ctx->fs, ctx->smoothing_s));
  return ctx->aux_rate.back().second;
}

// The aux_hysteresis state of a component's channel, computed once per context.
const Eigen::VectorXd& AuxState(Context* ctx, const DeterministicComponent& component) {
  for (const auto& [channel, state] : ctx->aux_state)
    if (channel == component.term.channel) return state;
  const Eigen::VectorXd& derivative = AuxRate(ctx, component.term.channel);
  ctx->aux_state.emplace_back(
      component.term.channel,
      HysteresisState(derivative, component.reference, ctx->fs, ctx->smoothing_s));
  return ctx->aux_state.back().second;
}

Eigen::MatrixXd Columns(const Context& ctx, Term term, double nonlinear);

// Columns of one component: (x - x_ref)^k, k = 1..order for aux:<x>; dx/dt for aux_rate:<x>;
// the rising/falling state for aux_hysteresis:<x>; the line's cosine and sine, then both times
// x - x_ref, for aux_am:<x>.
Eigen::MatrixXd ComponentColumns(const Context& ctx, const DeterministicComponent& component,
                                 int order) {
  if (component.term == Term::kBiasLevels) {
    // One bias_step column per step.
    Eigen::MatrixXd columns(ctx.n, static_cast<long>(component.step_times_s.size()));
    for (long j = 0; j < columns.cols(); ++j)
      columns.col(j) = Columns(ctx, Term::kBiasStep, component.step_times_s[j]);
    return columns;
  }
  if (!component.term.IsAux()) return Columns(ctx, component.term.term, component.nonlinear);
  if (component.term.aux == AuxForm::kAm) {
    const Eigen::VectorXd* values = AuxValues(ctx, component.term.channel);
    if (values == nullptr) return Eigen::MatrixXd(ctx.n, 0);
    Eigen::MatrixXd columns(ctx.n, 4);
    columns.leftCols(2) = Columns(ctx, Term::kSinusoid, component.nonlinear);
    const Eigen::ArrayXd centered = values->array() - component.reference;
    for (int j = 0; j < 2; ++j) columns.col(2 + j) = (columns.col(j).array() * centered).matrix();
    return columns;
  }
  if (component.term.aux == AuxForm::kRate || component.term.aux == AuxForm::kHysteresis) {
    // Computed beforehand (AuxRate, AuxState): the context is shared and read-only here.
    const auto& series = component.term.aux == AuxForm::kRate ? ctx.aux_rate : ctx.aux_state;
    for (const auto& [channel, column] : series)
      if (channel == component.term.channel) return Eigen::MatrixXd(column);
    return Eigen::MatrixXd(ctx.n, 0);
  }
  const Eigen::VectorXd* values = AuxValues(ctx, component.term.channel);
  if (values == nullptr) return Eigen::MatrixXd(ctx.n, 0);
  Eigen::MatrixXd columns(ctx.n, order);
  const Eigen::ArrayXd centered = values->array() - component.reference;
  Eigen::ArrayXd power = centered;
  for (int k = 0; k < order; ++k) {
    columns.col(k) = power.matrix();
    power *= centered;
  }
  return columns;
}

// Columns of one component at its current nonlinear parameter.
Eigen::MatrixXd Columns(const Context& ctx, Term term, double nonlinear) {
  const long n = ctx.n;
  switch (term) {
    case Term::kTemperature:
      return ctx.temperature_centered;
    case Term::kTemperatureRate:
      return ctx.temperature_rate;
    case Term::kSinusoid: {
      // Rotation recurrence, re-anchored on exact values every kAnchor samples (rounding error
      // stays ~kAnchor * eps), ~10x faster than cos/sin per sample.
      Eigen::MatrixXd columns(n, 2);
      const double angular_frequency = 2 * units::kPi * nonlinear;
      const std::complex<double> rot = std::polar(1.0, angular_frequency / ctx.fs);
      std::complex<double> z;
      for (long i = 0; i < n; ++i) {
        z = (i % kAnchor == 0) ? std::polar(1.0, angular_frequency * ctx.t[i]) : z * rot;
        columns(i, 0) = z.real();
        columns(i, 1) = z.imag();
      }
      return columns;
    }
    case Term::kBiasStep: {
      Eigen::MatrixXd columns(n, 1);
      for (long i = 0; i < n; ++i) columns(i, 0) = ctx.t[i] >= nonlinear ? 1.0 : 0.0;
      return columns;
    }
    case Term::kWarmup: {
      Eigen::MatrixXd columns(n, 1);
      const double decay = std::exp(-1.0 / (ctx.fs * nonlinear));
      double decay_value = 1.0;
      for (long i = 0; i < n; ++i) {
        decay_value = (i % kAnchor == 0) ? std::exp(-ctx.t[i] / nonlinear) : decay_value * decay;
        columns(i, 0) = decay_value;
      }
      return columns;
    }
    default:
      return Eigen::MatrixXd(n, 0);
  }
}

bool HasNonlinear(const ModelTerm& term) {
  return IsLine(term) || term == Term::kBiasStep || term == Term::kBiasLevels ||
         term == Term::kWarmup;
}

// The number of linear coefficients of a component.
long Width(const DeterministicComponent& component) {
  if (component.term == Term::kSinusoid) return 2;
  if (component.term.aux == AuxForm::kAm) return 4;
  if (component.term == Term::kBiasLevels) return static_cast<long>(component.step_times_s.size());
  if (component.term.aux == AuxForm::kValue)
    return std::max<long>(1, static_cast<long>(component.coefficients.size()));
  return 1;
}

// Solves the normal equations with Jacobi scaling (columns of very different magnitude: degC,
// degC/s, 1) so that LDLT sees a condition number of the correlation matrix, not of the units.
Eigen::VectorXd SolveScaled(const Eigen::MatrixXd& matrix, const Eigen::VectorXd& rhs) {
  Eigen::VectorXd scale = matrix.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd scaled = scale.asDiagonal() * matrix * scale.asDiagonal();
  Eigen::VectorXd solution = scaled.ldlt().solve(scale.asDiagonal() * rhs);
  return scale.asDiagonal() * solution;
}

Eigen::MatrixXd InverseScaled(const Eigen::MatrixXd& matrix) {
  Eigen::VectorXd scale = matrix.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd scaled = scale.asDiagonal() * matrix * scale.asDiagonal();
  Eigen::MatrixXd scaled_inverse =
      scaled.ldlt().solve(Eigen::MatrixXd::Identity(matrix.rows(), matrix.cols()));
  return scale.asDiagonal() * scaled_inverse * scale.asDiagonal();
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
    const long num_fixed = fixed_.cols(), num_extra = extra.cols();
    Eigen::MatrixXd normal_matrix(num_fixed + num_extra, num_fixed + num_extra);
    Eigen::VectorXd normal_rhs(num_fixed + num_extra);
    normal_matrix.topLeftCorner(num_fixed, num_fixed) = gram_;
    normal_matrix.topRightCorner(num_fixed, num_extra) = fixed_.transpose() * extra;
    normal_matrix.bottomLeftCorner(num_extra, num_fixed) =
        normal_matrix.topRightCorner(num_fixed, num_extra).transpose();
    normal_matrix.bottomRightCorner(num_extra, num_extra) = extra.transpose() * extra;
    normal_rhs.head(num_fixed) = xty_;
    normal_rhs.tail(num_extra) = extra.transpose() * y_;
    const Eigen::VectorXd beta = SolveScaled(normal_matrix, normal_rhs);
    return yy_ - normal_rhs.dot(beta);
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

Eigen::MatrixXd Design(const Context& ctx, const std::vector<DeterministicComponent>& components,
                       int skip) {
  long cols = 1;
  std::vector<Eigen::MatrixXd> parts;
  for (int i = 0; i < static_cast<int>(components.size()); ++i) {
    if (i == skip) continue;
    parts.push_back(ComponentColumns(ctx, components[i], static_cast<int>(Width(components[i]))));
    cols += parts.back().cols();
  }
  Eigen::MatrixXd design(ctx.n, cols);
  design.col(0).setOnes();
  long column = 1;
  for (const auto& part : parts) {
    design.middleCols(column, part.cols()) = part;
    column += part.cols();
  }
  return design;
}

double SearchWarmup(const Context& ctx, const Profiler& profiler,
                    const DeterministicOptions& options) {
  const double record_s = ctx.n / ctx.fs;
  const double lo = std::log(std::max(options.min_warmup_tau_s, 3.0 / ctx.fs));
  const double hi = std::log(record_s / 3.0);
  const int grid = 24;
  int best_index = 0;
  double best_rss = std::numeric_limits<double>::infinity();
  for (int i = 0; i < grid; ++i) {
    const double tau = std::exp(lo + (hi - lo) * i / (grid - 1));
    const double rss = profiler.Rss(Columns(ctx, Term::kWarmup, tau));
    if (rss < best_rss) {
      best_rss = rss;
      best_index = i;
    }
  }
  const double step = (hi - lo) / (grid - 1);
  const double bracket_low = lo + step * std::max(best_index - 1, 0),
               bracket_high = lo + step * std::min(best_index + 1, grid - 1);
  return std::exp(GoldenMinimize(
      [&](double log_tau) { return profiler.Rss(Columns(ctx, Term::kWarmup, std::exp(log_tau))); },
      bracket_low, bracket_high, 20));
}

double SearchStep(const Context& ctx, const Profiler& profiler,
                  const DeterministicOptions& options) {
  const Eigen::VectorXd residual = profiler.FixedResidual();
  const long n = ctx.n;
  const long first_index = std::max(1L, static_cast<long>(options.step_margin_fraction * n));
  const long end_index = std::min(n - 1, n - first_index);
  double cumulative_sum = 0, best_stat = -1;
  long best_index = n / 2;
  for (long k = 1; k < end_index; ++k) {
    // Sum of residual[0..k-1]; a step at sample k splits [0,k) and [k,n).
    cumulative_sum += residual[k - 1];
    if (k < first_index) continue;
    const double stat = cumulative_sum * cumulative_sum / (static_cast<double>(k) * (n - k));
    if (stat > best_stat) {
      best_stat = stat;
      best_index = k;
    }
  }
  return best_index / ctx.fs;
}

// The columns of a line component (sinusoid, aux_am) at a trial frequency.
Eigen::MatrixXd LineColumns(const Context& ctx, const DeterministicComponent& component,
                            double frequency_hz) {
  DeterministicComponent at = component;
  at.nonlinear = frequency_hz;
  return ComponentColumns(ctx, at, static_cast<int>(Width(at)));
}

// The frequency of a line component (sinusoid, aux_am): the largest periodogram peak over its
// band-median background, away from the lines already taken, refined on the component's profile
// RSS (for aux_am the four columns: the carrier is the largest peak of an amplitude-modulated
// line, and its sidebands' power enters the profile).
double SearchSinusoid(const Context& ctx, const Profiler& profiler,
                      const DeterministicOptions& options, const DeterministicComponent& component,
                      const std::vector<double>& taken_hz) {
  const Eigen::VectorXd residual = profiler.FixedResidual();
  const Spectrum spectrum = Periodogram(residual, ctx.fs, 2);
  const std::vector<double> background = BandMedianBackground(spectrum, 1.25, 33);
  const double record_s = ctx.n / ctx.fs;
  const double min_frequency_hz = options.min_sinusoid_cycles / record_s;
  int best_bin = -1;
  double best_ratio = -1;
  for (size_t k = 1; k + 1 < spectrum.psd.size(); ++k) {
    const double frequency_hz = spectrum.frequency_hz[k];
    if (frequency_hz < min_frequency_hz) continue;
    bool near = false;
    for (double taken : taken_hz) near = near || std::abs(frequency_hz - taken) < 2.0 / record_s;
    if (near || background[k] <= 0) continue;
    const double ratio = spectrum.psd[k] / background[k];
    if (ratio > best_ratio) {
      best_ratio = ratio;
      best_bin = static_cast<int>(k);
    }
  }
  if (best_bin < 0) return min_frequency_hz;
  const double bin_width_hz = spectrum.frequency_hz[1];
  const double peak_hz = spectrum.frequency_hz[best_bin];
  return GoldenMinimize(
      [&](double frequency_hz) { return profiler.Rss(LineColumns(ctx, component, frequency_hz)); },
      std::max(peak_hz - 1.5 * bin_width_hz, 0.5 * min_frequency_hz), peak_hz + 1.5 * bin_width_hz,
      22);
}

double RefineSinusoid(const Context& ctx, const Profiler& profiler,
                      const DeterministicComponent& component) {
  const double half_bin_hz = 0.5 * ctx.fs / ctx.n;
  return GoldenMinimize(
      [&](double trial_hz) { return profiler.Rss(LineColumns(ctx, component, trial_hz)); },
      component.nonlinear - half_bin_hz, component.nonlinear + half_bin_hz, 14);
}

double SearchNonlinear(const Context& ctx, const Profiler& profiler,
                       const DeterministicOptions& options, const DeterministicComponent& component,
                       bool refine, const std::vector<double>& taken_hz) {
  if (IsLine(component.term))
    return refine ? RefineSinusoid(ctx, profiler, component)
                  : SearchSinusoid(ctx, profiler, options, component, taken_hz);
  if (component.term.IsAux()) return 0.0;
  switch (component.term.term) {
    case Term::kWarmup:
      return SearchWarmup(ctx, profiler, options);  // cheap: always the full search
    case Term::kBiasStep:
      return SearchStep(ctx, profiler, options);
    default:
      return 0.0;
  }
}

// Order of initialisation: the largest, slowest effects first, so that later searches see a
// residual already cleared of them; an AM line before the sinusoids: its carrier and sidebands
// are one line, which a sinusoid
// searched first would split (the carrier to the sinusoid, a sideband to the AM line's search,
// which avoids the frequencies already taken).
int InitOrder(const ModelTerm& term) {
  if (term.IsAux()) return term.aux == AuxForm::kAm ? 4 : 0;
  switch (term.term) {
    case Term::kTemperature:
      return 0;
    case Term::kTemperatureRate:
      return 1;
    case Term::kWarmup:
      return 2;
    case Term::kBiasStep:
    case Term::kBiasLevels:
      return 3;
    default:
      return 5;
  }
}

}  // namespace

bool DeterministicOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (!(temperature_smoothing_s >= 0)) return fail("temperature_smoothing_s must be >= 0");
  if (!(step_margin_fraction > 0 && step_margin_fraction < 0.5))
    return fail("step_margin_fraction must be in (0, 0.5)");
  if (!(min_warmup_tau_s > 0)) return fail("min_warmup_tau_s must be > 0");
  if (!(min_sinusoid_cycles >= 1)) return fail("min_sinusoid_cycles must be >= 1");
  if (refinement_passes < 0) return fail("refinement_passes must be >= 0");
  if (max_aux_order < 1) return fail("max_aux_order must be >= 1");
  return true;
}

namespace {

// The half-width h of the centred window [i - h, i + h] of SmoothedDerivative, samples.
long SmoothingHalfWidth(double fs, double smoothing_s) {
  return std::max(1L, static_cast<long>(std::lround(0.5 * smoothing_s * fs)));
}

// The noise gain of a least-squares slope over `count` equally spaced samples, per sample
// interval: sd(slope) = sigma sqrt(12 / (count (count^2 - 1))) for white noise of sd sigma.
double SlopeNoiseGain(long count) {
  const double m = static_cast<double>(std::max(2L, count));
  return std::sqrt(12.0 / (m * (m * m - 1)));
}

// SmoothedDerivative's window at sample i of n: [lo, hi], clipped at the record's ends.
std::pair<long, long> Window(long i, long n, long half_width) {
  return {std::max(0L, i - half_width), std::min(n - 1, i + half_width)};
}

// The number of samples in that window, and in the widest (interior) one.
long WindowCount(long i, long n, long half_width) {
  const auto [lo, hi] = Window(i, n, half_width);
  return hi - lo + 1;
}
long InteriorWindowCount(long n, long half_width) { return std::min(n, 2 * half_width + 1); }

}  // namespace

Eigen::VectorXd SmoothedDerivative(const Eigen::VectorXd& temp, double fs, double smoothing_s) {
  // Slope of a local least-squares line over the centred window [i - h, i + h], clipped at the
  // record ends (Savitzky & Golay 1964, first order). Unlike differencing a moving average, it
  // stays unbiased for a linear trend at the ends, where a warm-up would otherwise absorb the
  // error. Prefix sums of k, k^2, x, k x make it O(n).
  const long n = temp.size();
  if (n < 2) return Eigen::VectorXd::Zero(n);
  const long half_width = SmoothingHalfWidth(fs, smoothing_s);
  Eigen::VectorXd sk(n + 1), skk(n + 1), sx(n + 1), skx(n + 1);
  sk[0] = skk[0] = sx[0] = skx[0] = 0;
  for (long i = 0; i < n; ++i) {
    const double k = static_cast<double>(i);
    sk[i + 1] = sk[i] + k;
    skk[i + 1] = skk[i] + k * k;
    sx[i + 1] = sx[i] + temp[i];
    skx[i + 1] = skx[i] + k * temp[i];
  }
  Eigen::VectorXd derivative(n);
  for (long i = 0; i < n; ++i) {
    const auto [lo, hi] = Window(i, n, half_width);
    const double count = static_cast<double>(hi - lo + 1);
    // Centre k on i for conditioning: sums of (k - i) and (k - i)^2.
    const double ci = static_cast<double>(i);
    const double s1 = sk[hi + 1] - sk[lo], s2 = skk[hi + 1] - skk[lo];
    const double sxv = sx[hi + 1] - sx[lo], skxv = skx[hi + 1] - skx[lo];
    const double u = s1 - count * ci, uu = s2 - 2 * ci * s1 + count * ci * ci, ux = skxv - ci * sxv;
    const double denominator = uu - u * u / count;
    derivative[i] = denominator > 0 ? (ux - u * sxv / count) / denominator * fs : 0.0;
  }
  return derivative;
}

double HysteresisDeadBand(const Eigen::VectorXd& values, double fs, double smoothing_s) {
  const long n = values.size();
  if (n < 2) return 0.0;
  const double sensor_sd =
      std::sqrt((values.tail(n - 1) - values.head(n - 1)).squaredNorm() / (n - 1) / 2.0);
  // The interior (widest) window of SmoothedDerivative.
  const long count = InteriorWindowCount(n, SmoothingHalfWidth(fs, smoothing_s));
  const double universal = std::sqrt(2.0 * std::log(static_cast<double>(n)));
  return universal * fs * SlopeNoiseGain(count) * sensor_sd;
}

Eigen::VectorXd HysteresisState(const Eigen::VectorXd& derivative, double dead_band, double fs,
                                double smoothing_s) {
  const long n = derivative.size();
  const long half_width = SmoothingHalfWidth(fs, smoothing_s);
  const double interior_gain = SlopeNoiseGain(InteriorWindowCount(n, half_width));
  Eigen::VectorXd state = Eigen::VectorXd::Zero(n);
  long first = -1;
  double current = 0.0;
  for (long i = 0; i < n; ++i) {
    // Near the record's ends the window is clipped and the slope noisier: the band widens with it.
    const double band = dead_band * SlopeNoiseGain(WindowCount(i, n, half_width)) / interior_gain;
    if (derivative[i] > band) current = 1.0;
    if (derivative[i] < -band) current = -1.0;
    if (current != 0.0 && first < 0) first = i;
    state[i] = current;
  }
  if (first > 0) state.head(first).setConstant(state[first]);
  return state;
}

namespace {

// Long-run to short-run variance ratio of a residual by batch means over kSandwichBlocks blocks,
// at least 1; sigma2 is the short-run (per-sample) variance.
double LongRunVarianceRatio(const Eigen::VectorXd& residual, double sigma2) {
  const long n = residual.size(), block = n / kSandwichBlocks;
  Eigen::VectorXd block_means(kSandwichBlocks);
  for (int block_index = 0; block_index < kSandwichBlocks; ++block_index) {
    const long start = block_index * block,
               length = (block_index == kSandwichBlocks - 1) ? n - start : block;
    block_means[block_index] = residual.segment(start, length).mean();
  }
  const double block_mean_variance =
      (block_means.array() - block_means.mean()).square().sum() / (kSandwichBlocks - 1);
  return std::max(1.0, block * block_mean_variance / std::max(sigma2, 1e-300));
}

// The components of `terms` that are fitted on the rate, or an error message.
std::string MakeComponents(const Context& ctx, const std::vector<ModelTerm>& terms,
                           std::vector<DeterministicComponent>* components) {
  const auto has = [&](const ModelTerm& term) {
    return std::find(terms.begin(), terms.end(), term) != terms.end();
  };
  for (const ModelTerm& term : terms) {
    if (!IsFittedOnRate(term)) continue;
    const std::string channel = AuxChannelOf(term);
    if (!channel.empty() && AuxValues(ctx, channel) == nullptr)
      return "term '" + ToString(term) + "' needs an aux " + channel +
             " channel of the rate's length";
    if (const std::optional<Term> within = ThermalTermWithin(term); within && has(*within)) {
      return ToString(term) + (term.aux == AuxForm::kRate ? " is the " : " contains the ") +
             ToString(*within) + " term; the model may have one of them";
    }
    if (term.IsAux() && std::count(terms.begin(), terms.end(), term) > 1)
      return "term '" + ToString(term) + "' is in the model twice";
    DeterministicComponent component;
    component.term = term;
    if (term.IsAux()) {
      const Eigen::VectorXd& values = *AuxValues(ctx, channel);
      component.reference = term.aux == AuxForm::kHysteresis
                                ? HysteresisDeadBand(values, ctx.fs, ctx.smoothing_s)
                                : values.mean();
      for (const auto& series : ctx.aux)
        if (series.name == channel) component.units = series.units;
      component.coefficients.assign(1, 0.0);
    }
    components->push_back(component);
  }
  std::stable_sort(components->begin(), components->end(), [](const auto& lhs, const auto& rhs) {
    return InitOrder(lhs.term) < InitOrder(rhs.term);
  });
  return "";
}

// Chooses the order of each aux:<channel> polynomial by BIC (deterministic_fit.h), the other
// components at their current parameters, one polynomial after the other.
void ChooseAuxOrders(const Context& ctx, const Eigen::VectorXd& rate, int max_order,
                     std::vector<DeterministicComponent>* components) {
  const double n = static_cast<double>(ctx.n);
  for (auto& component : *components) {
    if (component.term.aux != AuxForm::kValue) continue;
    std::vector<double> rss(max_order + 1, 0.0);
    double n_eff = n;
    long base_parameters = 0;
    for (int order = 1; order <= max_order; ++order) {
      component.coefficients.assign(order, 0.0);
      const Eigen::MatrixXd design = Design(ctx, *components, -1);
      const Eigen::VectorXd beta =
          SolveScaled(design.transpose() * design, design.transpose() * rate);
      const Eigen::VectorXd residual = rate - design * beta;
      rss[order] = residual.squaredNorm();
      if (order == 1) {
        base_parameters = design.cols();
        const double sigma2 = rss[1] / std::max(1.0, n - static_cast<double>(design.cols()));
        n_eff = n / LongRunVarianceRatio(residual, sigma2);
      }
    }
    int best = 1;
    double best_bic = std::numeric_limits<double>::infinity();
    for (int order = 1; order <= max_order; ++order) {
      const double bic = n_eff * std::log(std::max(rss[order], 1e-300)) +
                         static_cast<double>(base_parameters + order - 1) * std::log(n_eff);
      if (bic < best_bic) {
        best_bic = bic;
        best = order;
      }
    }
    component.coefficients.assign(best, 0.0);
  }
}

}  // namespace

std::vector<AuxSeries> TemperatureSeries(const Eigen::VectorXd* temperature_degc) {
  if (temperature_degc == nullptr) return {};
  return {{"temperature", "degC", temperature_degc}};
}

DeterministicFit FitDeterministic(const Eigen::VectorXd& rate, double fs,
                                  const Eigen::VectorXd* temperature,
                                  const std::vector<ModelTerm>& terms,
                                  const DeterministicOptions& options) {
  return FitDeterministic(rate, fs, TemperatureSeries(temperature), terms, options);
}

DeterministicFit FitDeterministic(const Eigen::VectorXd& rate, double fs,
                                  const std::vector<AuxSeries>& aux,
                                  const std::vector<ModelTerm>& terms,
                                  const DeterministicOptions& options) {
  DeterministicFit fit;
  fit.summary.num_samples = rate.size();
  std::string err;
  if (!options.IsValid(&err) || !(fs > 0)) {
    fit.summary.termination = Termination::kInvalidOptions;
    fit.summary.message = fs > 0 ? err : "sample_rate_hz must be > 0";
    return fit;
  }
  Context ctx;
  ctx.n = rate.size();
  ctx.fs = fs;
  ctx.aux = aux;
  ctx.smoothing_s = options.temperature_smoothing_s;
  if (ctx.n < 64) {
    fit.summary.termination = Termination::kInsufficientData;
    fit.summary.message = "fewer than 64 samples";
    return fit;
  }
  ctx.t = Eigen::VectorXd::LinSpaced(ctx.n, 0.0, (ctx.n - 1) / fs);
  fit.model.temperature_smoothing_s = options.temperature_smoothing_s;

  std::vector<DeterministicComponent> components;
  if (const std::string problem = MakeComponents(ctx, terms, &components); !problem.empty()) {
    fit.summary.termination = Termination::kInsufficientData;
    fit.summary.message = problem;
    return fit;
  }
  for (const auto& component : components) {
    if (component.term.aux != AuxForm::kAm) continue;
    // A constant channel makes the modulation's columns zero: the amplitude's change with it is
    // not identifiable.
    const Eigen::VectorXd& values = *AuxValues(ctx, component.term.channel);
    if (values.maxCoeff() == values.minCoeff()) {
      fit.summary.termination = Termination::kInsufficientData;
      fit.summary.message = "term '" + ToString(component.term) +
                            "': the channel is constant (the line's amplitude cannot follow it)";
      return fit;
    }
  }
  for (const auto& component : components) {
    if (!UsesDerivative(component.term) || !component.term.IsAux()) continue;
    AuxRate(&ctx, component.term.channel);
    if (component.term.aux != AuxForm::kHysteresis) continue;
    // A state of one sign all along (a channel that only rises, as in a warm-up, or never leaves
    // the band) is the bias column itself, or zero: the coefficient is not identifiable.
    const Eigen::VectorXd& state = AuxState(&ctx, component);
    if (!(state.maxCoeff() > 0.0 && state.minCoeff() < 0.0)) {
      fit.summary.termination = Termination::kInsufficientData;
      fit.summary.message = "term '" + ToString(component.term) + "': the channel " +
                            (state.isZero() ? "never leaves the dead band (it neither rises nor "
                                              "falls beyond its noise)"
                                            : "moves one way only (it never both rises and falls "
                                              "beyond its noise)");
      return fit;
    }
  }
  if (const Eigen::VectorXd* temperature = AuxValues(ctx, "temperature")) {
    fit.model.temperature_ref_degc = temperature->mean();
    ctx.temperature_centered = temperature->array() - fit.model.temperature_ref_degc;
    if (std::any_of(terms.begin(), terms.end(),
                    [](const ModelTerm& term) { return term == Term::kTemperatureRate; }))
      ctx.temperature_rate = SmoothedDerivative(*temperature, fs, options.temperature_smoothing_s);
  }

  // Initialise the nonlinear parameters one at a time, then coordinate descent.
  const int num_components = static_cast<int>(components.size());
  for (int pass = 0; pass <= options.refinement_passes; ++pass) {
    for (int i = 0; i < num_components; ++i) {
      if (!HasNonlinear(components[i].term)) continue;
      // During initialisation only the components already placed enter the fixed design.
      std::vector<DeterministicComponent> placed;
      std::vector<double> taken_hz;
      for (int j = 0; j < num_components; ++j) {
        if (j == i) continue;
        if (pass == 0 && j > i && HasNonlinear(components[j].term)) continue;
        placed.push_back(components[j]);
        if (IsLine(components[j].term)) taken_hz.push_back(components[j].nonlinear);
      }
      const Eigen::MatrixXd fixed = Design(ctx, placed, -1);
      const Profiler profiler(fixed, rate);
      if (components[i].term == Term::kBiasLevels) {
        const LevelsSegmentation segmentation =
            SegmentLevels(profiler.FixedResidual(), fs, LevelsOptions{});
        components[i].step_times_s.clear();
        for (long index : segmentation.step_index) components[i].step_times_s.push_back(index / fs);
        components[i].levels_delta_bic =
            segmentation.penalty * static_cast<double>(segmentation.step_index.size()) -
            segmentation.gain;
        components[i].levels_too_many_steps = segmentation.too_many_steps;
        components[i].levels_max_design_steps = segmentation.max_design_steps;
        continue;
      }
      components[i].nonlinear =
          SearchNonlinear(ctx, profiler, options, components[i], pass > 0, taken_hz);
    }
  }

  ChooseAuxOrders(ctx, rate, options.max_aux_order, &components);

  // Final joint linear solve.
  const Eigen::MatrixXd design = Design(ctx, components, -1);
  const Eigen::MatrixXd gram = design.transpose() * design;
  const Eigen::VectorXd beta = SolveScaled(gram, design.transpose() * rate);
  fit.residual = rate - design * beta;
  fit.rss = fit.residual.squaredNorm();
  if (!std::isfinite(fit.rss)) {
    fit.summary.termination = Termination::kNumericalFailure;
    fit.summary.message = "non-finite residual";
    return fit;
  }

  // Linearised design for the standard errors: amplitudes plus d(model)/d(nonlinear parameter).
  std::vector<Eigen::VectorXd> jacobian_columns;
  {
    long column = 1;
    for (auto& component : components) {
      const long width = Width(component);
      if (component.term == Term::kSinusoid) {
        const double angular_frequency = 2 * units::kPi * component.nonlinear;
        const double cos_coefficient = beta[column], sin_coefficient = beta[column + 1];
        Eigen::VectorXd jacobian(ctx.n);
        for (long i = 0; i < ctx.n; ++i)
          jacobian[i] = 2 * units::kPi * ctx.t[i] *
                        (-cos_coefficient * std::sin(angular_frequency * ctx.t[i]) +
                         sin_coefficient * std::cos(angular_frequency * ctx.t[i]));
        jacobian_columns.push_back(jacobian);
      } else if (component.term.aux == AuxForm::kAm) {
        // d/df of (c0 + c1 x~) cos(2 pi f t) + (s0 + s1 x~) sin(2 pi f t), the columns being
        // cos, sin, x~ cos, x~ sin: 2 pi t [-(c0 + c1 x~) sin + (s0 + s1 x~) cos].
        const Eigen::MatrixXd columns = ComponentColumns(ctx, component, 4);
        const Eigen::VectorXd envelope_derivative =
            -beta[column] * columns.col(1) + beta[column + 1] * columns.col(0) -
            beta[column + 2] * columns.col(3) + beta[column + 3] * columns.col(2);
        jacobian_columns.push_back(
            (2 * units::kPi * ctx.t.array() * envelope_derivative.array()).matrix());
      } else if (component.term == Term::kWarmup) {
        const double amplitude = beta[column], tau = component.nonlinear;
        jacobian_columns.push_back((amplitude / (tau * tau)) * ctx.t.array() *
                                   (-ctx.t.array() / tau).exp());
      }
      column += width;
    }
  }
  const long num_linear = design.cols(), num_jacobian = static_cast<long>(jacobian_columns.size());
  Eigen::MatrixXd augmented(ctx.n, num_linear + num_jacobian);
  augmented.leftCols(num_linear) = design;
  for (long j = 0; j < num_jacobian; ++j) augmented.col(num_linear + j) = jacobian_columns[j];
  const Eigen::MatrixXd bread = InverseScaled(augmented.transpose() * augmented);
  const double sigma2 =
      fit.rss / std::max(1.0, static_cast<double>(ctx.n - num_linear - num_jacobian));
  Eigen::MatrixXd meat =
      Eigen::MatrixXd::Zero(num_linear + num_jacobian, num_linear + num_jacobian);
  const long block = ctx.n / kSandwichBlocks;
  for (int block_index = 0; block_index < kSandwichBlocks; ++block_index) {
    const long block_start = block_index * block,
               block_length = (block_index == kSandwichBlocks - 1) ? ctx.n - block_start : block;
    const Eigen::VectorXd block_score =
        augmented.middleRows(block_start, block_length).transpose() *
        fit.residual.segment(block_start, block_length);
    meat += block_score * block_score.transpose();
  }
  const Eigen::MatrixXd cov_hac = bread * meat * bread;
  // The OLS floor takes the residual as white at its total variance. For aux_am's columns, a line
  // whose energy sits at its frequency f (far above the blocks' 1 / (T / 32)), the sandwich
  // already measures the residual's power near f, and the total variance is ruled by the
  // quantization's blue noise (at 10 Hz, 2-4x the white noise's per sample, far less near f): the
  // floor made their errors 2-3x too large (sd of (estimate - truth) / SE 0.3-0.5 over seeds).
  std::vector<bool> sandwich_only(num_linear + num_jacobian, false);
  {
    long column = 1, jacobian_column = num_linear;
    for (const auto& component : components) {
      const long width = Width(component);
      const bool am = component.term.aux == AuxForm::kAm;
      for (long j = 0; j < width; ++j) sandwich_only[column + j] = am;
      if (IsLine(component.term) || component.term == Term::kWarmup)
        sandwich_only[jacobian_column++] = am;
      column += width;
    }
  }
  Eigen::VectorXd se(num_linear + num_jacobian);
  for (long j = 0; j < num_linear + num_jacobian; ++j)
    se[j] =
        std::sqrt(sandwich_only[j] ? cov_hac(j, j) : std::max(cov_hac(j, j), sigma2 * bread(j, j)));
  fit.long_run_variance_ratio = LongRunVarianceRatio(fit.residual, sigma2);

  // Hinkley's (1970) scale of a change-point time: sigma_lr^2 / D^2, in s.
  const auto StepTimeSe = [&](double step_size) {
    return fit.long_run_variance_ratio * sigma2 / std::max(step_size * step_size, 1e-300) / fs;
  };
  fit.model.bias_rad_s = beta[0];
  fit.model.bias_se_rad_s = se[0];
  long column = 1, jacobian_column = num_linear;
  for (auto& component : components) {
    const long width = Width(component);
    component.coefficients.assign(beta.data() + column, beta.data() + column + width);
    component.coefficients_se.assign(se.data() + column, se.data() + column + width);
    component.coefficients_covariance.clear();
    if (component.term.aux == AuxForm::kAm)
      for (long i = 0; i < width; ++i)
        for (long j = 0; j < width; ++j)
          component.coefficients_covariance.push_back(cov_hac(column + i, column + j));
    if (IsLine(component.term) || component.term == Term::kWarmup) {
      component.nonlinear_se = se[jacobian_column++];
    } else if (component.term == Term::kBiasStep) {
      component.nonlinear_se = StepTimeSe(beta[column]);
    } else if (component.term == Term::kBiasLevels) {
      component.step_times_se_s.clear();
      for (long j = 0; j < width; ++j)
        component.step_times_se_s.push_back(StepTimeSe(beta[column + j]));
    }
    column += width;
  }
  fit.model.components = components;
  fit.summary.num_parameters = static_cast<int>(
      num_linear + num_jacobian +
      std::accumulate(components.begin(), components.end(), 0L,
                      [](long sum, const auto& component) {
                        // The step times are parameters too.
                        if (component.term == Term::kBiasStep) return sum + 1;
                        if (component.term == Term::kBiasLevels)
                          return sum + static_cast<long>(component.step_times_s.size());
                        return sum;
                      }));
  fit.summary.message =
      "fitted " + std::to_string(components.size()) + " deterministic component(s)";
  return fit;
}

Eigen::VectorXd EvaluateDeterministic(const DeterministicModel& model, long n, double fs,
                                      const Eigen::VectorXd* temperature, bool include_bias) {
  return EvaluateDeterministic(model, n, fs, TemperatureSeries(temperature), include_bias);
}

Eigen::VectorXd EvaluateDeterministic(const DeterministicModel& model, long n, double fs,
                                      const std::vector<AuxSeries>& aux, bool include_bias) {
  Context ctx;
  ctx.n = n;
  ctx.fs = fs;
  ctx.aux = aux;
  ctx.smoothing_s = model.temperature_smoothing_s;
  ctx.t = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / fs);
  if (const Eigen::VectorXd* temperature = AuxValues(ctx, "temperature")) {
    ctx.temperature_centered = temperature->array() - model.temperature_ref_degc;
    ctx.temperature_rate = SmoothedDerivative(*temperature, fs, model.temperature_smoothing_s);
  }
  Eigen::VectorXd rate = Eigen::VectorXd::Constant(n, include_bias ? model.bias_rad_s : 0.0);
  for (const auto& component : model.components) {
    const std::string channel = AuxChannelOf(component.term);
    if (!channel.empty() && AuxValues(ctx, channel) == nullptr) continue;
    if (component.term.IsAux() && UsesDerivative(component.term)) AuxRate(&ctx, channel);
    if (component.term.aux == AuxForm::kHysteresis) AuxState(&ctx, component);
    const Eigen::MatrixXd columns =
        ComponentColumns(ctx, component, static_cast<int>(Width(component)));
    for (long j = 0; j < columns.cols() && j < static_cast<long>(component.coefficients.size());
         ++j)
      rate += component.coefficients[j] * columns.col(j);
  }
  return rate;
}

}  // namespace fogpipe::model
