// The stochastic part of the gyro model, fitted on the Allan variance of what the deterministic
// part leaves (IEEE Std 952-1997 Annex C):
//
//   sigma^2(tau) = 3 Q^2 / tau^2 + N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3 + R^2 tau^2 / 2
//                  [+ Gauss-Markov (sigma, Tc)]
//
// Weighted non-negative least squares on sigma^2 (the coefficients are squares, so >= 0), with
// weights 1 / ((2/edf + c^2) model^2) (var(sigma^2_hat) = 2 sigma^4 / edf, plus the relative
// model-shape tolerance c of views.h), iterated three times with the model in the weights
// (iteratively reweighted, to avoid the downward bias of weighting by the data). The term laws and
// the Lawson-Hanson NNLS are fogpipe::allan's (noise_model.h, nnls.h); allan::FitNoiseTerms is not
// used directly because the model needs a Gauss-Markov column and the shape tolerance.
// The Gauss-Markov correlation time is found by a log-grid + golden-section search with the
// amplitudes profiled out. Its uncertainty is a profile interval (Venzon & Moolgavkar 1988): the
// cost, a chi-square in the fit's weights, is scaled by its dispersion cost / (points -
// parameters) when that exceeds 1 (quasi-likelihood, McCullagh & Nelder 1989, 9.2), and the
// interval holds the Tc within chi2_1(0.95) = 3.84 of the minimum; a flat or two-valleyed profile
// gives a wide interval where the local curvature would give a small standard error. The
// standard error of log Tc is the larger of the curvature's and the interval's half-width / 1.96.
// The amplitudes' standard errors are a sandwich (Huber 1967, White 1980) of the weighted fit with
// the Allan points' modelled covariance (allan/avar_covariance.h, Gauss-Markov term included:
// neighbouring overlapping points are strongly correlated, and the fit's weights take them as
// independent, which understates the errors), plus their trade-off with Tc (the delta method on
// the profile). PSD laws (two-sided, IEEE Std 952 Annex C) are given for the frequency
// view; they are the same processes as the Allan laws.
// Narrow bands (narrow_band.h) are fitted on the spectrum, not here: FitStochastic takes them as
// known and fits the other terms to what they leave, with the bands' Allan variance as a fixed
// offset of the model (in the target and in the weights).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/status.h"
#include "algorithms/model/catalog.h"
#include "algorithms/model/narrow_band.h"

namespace fogpipe::model {

/// Stochastic parameters, SI. A term not in `terms` is zero.
struct StochasticModel {
  std::vector<Term> terms;  ///< the stochastic terms in the model (white, quantization, ...)
  double q_rad = 0, q_se = 0;
  double n_rad_sqrt_s = 0, n_se = 0;
  double b_rad_s = 0, b_se = 0;
  double k_rad_s_sqrt_s = 0, k_se = 0;
  double r_rad_s2 = 0, r_se = 0;
  double gm_sigma_rad_s = 0, gm_sigma_se = 0;
  double gm_correlation_time_s = 0, gm_correlation_time_se = 0;
  /// The correlation time's 95 % profile interval [s] (FitStochastic): every Tc whose profiled
  /// cost is within the chi-square(1) 95 % point of the minimum. Tc is estimated on a log scale and
  /// its error is multiplicative: the interval, not value +- 2 SE, is what to quote. Equal to the
  /// search bound where the profile does not rise above the threshold before it.
  double gm_correlation_time_low_s = 0, gm_correlation_time_high_s = 0;
  std::vector<NarrowBand> bands;  ///< Term::kNarrowBand (in `terms` once, whatever their count)
  bool Has(Term t) const;
};

/// True for the terms FitStochastic fits on the Allan variance (white ... gauss_markov).
bool IsFittedOnAllan(Term term);

/// Unit-amplitude Allan law g(tau) of a stochastic term (fogpipe::allan's closed forms): the
/// term's Allan variance is P^2 g(tau) with P = Q, N, B, K, R or sigma; `tc_s` is the Gauss-Markov
/// correlation time (ignored by the other terms).
double UnitAllanLaw(Term term, double tau_s, double tc_s);
/// Allan variance of one term at tau (rad/s)^2 (Term::kSinusoid not included: fitted on rate).
double TermAllanVariance(const StochasticModel& model, Term term, double tau_s);
/// Sum over the model's terms.
double ModelAllanVariance(const StochasticModel& model, double tau_s);
/// One-sided PSD of the model's rate at frequency f, (rad/s)^2/Hz, for data sampled at fs
/// (quantization uses its exact discrete-time law 8 Q^2 fs sin^2(pi f / fs)).
double ModelOneSidedPsd(const StochasticModel& model, double frequency_hz, double sample_rate_hz);

struct StochasticFitOptions {
  /// Relative model-shape tolerance added to the sampling variance of sigma^2 (see views.h).
  double relative_floor = 0.05;
  /// Correlation times searched for gauss_markov: [min_tc_factor / fs, record / max_tc_divisor].
  double min_tc_factor = 2.0;
  double max_tc_divisor = 3.0;
  bool IsValid(std::string* error) const;
};

struct StochasticFitSummary {
  Termination termination = Termination::kSuccess;
  std::string message;
  int num_parameters = 0;
  double weighted_rss = 0;  ///< sum of w (s2 - model)^2 at the final weights (a chi-square)
};

struct StochasticFit {
  StochasticModel model;
  StochasticFitSummary summary;
};

/// Fits the stochastic terms of `terms` to Allan variances s2(tau) with their EDFs. `bands`
/// (known, fitted on the spectrum) enter the model as they are: the result has them and
/// Term::kNarrowBand when there is at least one.
StochasticFit FitStochastic(const std::vector<double>& tau_s, const std::vector<double>& avar,
                            const std::vector<double>& edf, double sample_rate_hz, double record_s,
                            const std::vector<Term>& terms, const StochasticFitOptions& options,
                            const std::vector<NarrowBand>& bands = {});

}  // namespace fogpipe::model
