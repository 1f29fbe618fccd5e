// Is the fitted bias instability, rate random walk or rate ramp what the long-tau data show, or
// is it absorbing a slow effect the model lacks? (`fogpipe compare`, a diagnostic beside the
// views, not part of the error.)
//
// Why. The Allan curve cannot tell these terms from slow deterministic effects: a bias step of
// size D adds D^2 tau / (3 T) to sigma^2(tau), exactly a rate random walk with K^2 = D^2 / T
// (targeted_tests.h); a few switching levels, a quadratic temperature dependence or a warm-up
// rise at long tau as K or R do. The fit then reads K many times its true value and every view
// passes. What does tell them apart is the time-domain structure at those taus: the increments
// of a random walk's block means are Gaussian and uncorrelated beyond the neighbouring block;
// those of a step are one large jump among small ones, those of a smooth effect are smooth.
//
// The check. At the octave taus where B, K and R carry at least `min_share` of the model's Allan
// variance and the record holds at least `min_blocks` non-overlapping blocks, take the block
// means y_j and their differences d_j = y_{j+1} - y_j (so 2 sigma^2(tau) = E d_j^2). Under the
// fitted model the d_j are a zero-mean Gaussian sequence with the Toeplitz covariance
//   gamma_k = tau^-2 sum_{p,q=0..2} a_p a_q C(|k + q - p| tau) + R^2 tau^2,  a = (1, -2, 1),
// where C is the generalised covariance of the integrated rate (the angle), an intrinsic random
// function of order 1 (Matheron 1973; second differences remove its polynomial part):
//   quantization Q^2 [h = 0],  white rate -N^2 h / 2,  bias instability (flicker) B^2 h^2 ln h /
//   (2 pi),  rate random walk K^2 h^3 / 12,  Gauss-Markov -sigma^2 Tc^2 (h / Tc - 1 + e^-h/Tc);
// a rate ramp is a constant d = R tau. gamma_0 / 2 is then each term's Allan law (IEEE Std 952
// Annex C; asserted in the test), and the neighbour correlation is -1/2 for white rate, +1/4 for a
// random walk. The sequence is whitened by its innovations (Durbin-Levinson), e_j ~ N(0, 1)
// independent under the model, and three scale-free statistics are computed per tau:
//   - jumps: the sample kurtosis of e, one-sided, by Anscombe & Glynn's (1983) normal deviate (a
//     few steps or switches among m increments give heavy tails, and unlike the largest
//     normed residual (Grubbs) it is not masked when there are several; the largest jump's time
//     is reported);
//   - smoothness: Ljung & Box's (1978) portmanteau m (m + 2) sum_{h=1..H} r_h^2 / (m - h) against
//     chi-square(H);
//   - levels or drift: the mean periodogram of e at the lowest J Fourier frequencies over its
//     mean over the first M = (m - 1) / 2, two-sided: the ordinates of white noise are
//     independent exponentials (Brockwell & Davis 1991, 10.3), so the ratio is (M / J) Beta(J,
//     M - J) (a sum of J of them over a sum of M), exactly. A random walk's block
//     means wander; levels that the record keeps returning to (a telegraph, a cycle) leave too
//     little power at the lowest frequencies of the increments, a smooth drift too much. This
//     is the frequency-domain form of a variance-ratio test (Lo & MacKinlay 1988).
// All three are self-normalised, so a level the Allan fit got slightly wrong does not trip them;
// they are judged at alpha' = alpha / (3 x taus tested) (Bonferroni over the family). A flag says
// the increments at those taus are not those of the fitted noise: the term that dominates there may
// be absorbing a slow effect (a step, levels, a thermal dependence), and its value is then an
// upper bound, not an estimate.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/model/stochastic_fit.h"

namespace fogpipe::model {

struct LongTauCheckOptions {
  /// Run the check. Only the base model's is read (compare.h), so Compare turns it off for its
  /// trial fits.
  bool enabled = true;
  /// Family-wise level of the flag per record, nominal. Below the usual 0.05 because the noise
  /// parameters are fitted on the same record, which widens the statistics' scatter beyond their
  /// laws (docs/compare.md has the measured rates).
  double alpha = 0.02;
  double min_share = 0.5;  ///< a tau is tested where B + K + R carry this share of the model AVAR
  int min_blocks = 21;     ///< non-overlapping blocks needed at a tested tau (>= 21)
  /// Taus with more blocks than this are skipped (the smaller taus): the long-tau terms are
  /// judged where they dominate, and the Durbin-Levinson recursion is O(blocks^2).
  int max_blocks = 4096;
  int max_lags = 8;  ///< Ljung-Box lags H = min(max_lags, max(2, (blocks - 1) / 4))
  bool IsValid(std::string* error) const;
};

/// One tested tau.
struct LongTauPoint {
  double tau_s = 0;
  int blocks = 0;
  std::string dominant_term;  ///< the catalog name of the largest of B, K, R at tau
  double share = 0;           ///< (B + K + R) AVAR / model AVAR at tau
  double kurtosis_z = 0;      ///< normal deviate of the whitened increments' kurtosis
  double kurtosis_critical = 0;
  double jump = 0;         ///< the largest whitened increment, |e - mean| / sd
  double jump_time_s = 0;  ///< the boundary between the two blocks of the largest jump
  double portmanteau = 0;  ///< Ljung-Box Q
  int lags = 0;
  double portmanteau_critical = 0;
  /// The mean periodogram of the whitened increments at the lowest low_bins Fourier frequencies
  /// over its mean at the first (m - 1) / 2 (1 expected) and its two-sided band.
  double low_frequency = 0;
  int low_bins = 0;
  double low_frequency_low = 0, low_frequency_high = 0;
  double low_frequency_level = 0;  ///< the band's coverage (1 - alpha / (3 x taus tested))
  bool flagged = false;
};

struct LongTauCheck {
  bool run = false;  ///< options.enabled (and valid): the check looked at the record
  bool evaluated = false;
  /// Not evaluated because B, K and R carry less than min_share of the model's Allan variance at
  /// every tau with min_blocks blocks: there is nothing for them to absorb (unlike the other
  /// reasons, a non-finite residual or a singular covariance, which say nothing).
  bool nothing_to_absorb = false;
  bool flagged = false;
  std::string message;  ///< why not evaluated, or the finding in one sentence
  std::vector<LongTauPoint> points;
};

/// The generalised covariance of the angle under `model` at lag h >= 0 (s), rad^2 (see above;
/// bands and sinusoids not included).
double AngleGeneralisedCovariance(const StochasticModel& model, double h_s);

/// Autocovariances gamma_0 .. gamma_{count-1} of the differences of tau-block means under
/// `model`, (rad/s)^2.
std::vector<double> BlockDifferenceAutocovariance(const StochasticModel& model, double tau_s,
                                                  int count);

/// Normal deviate of the sample kurtosis b2 of m normal values (Anscombe & Glynn 1983, the
/// kurtosis part of D'Agostino's K^2), positive for heavy tails.
double KurtosisNormalDeviate(double b2, int m);

/// P(Beta(a, b) <= x) and its p-quantile, for integer a, b >= 1 (the binomial sum).
double BetaCdf(double x, int a, int b);
double BetaQuantile(double p, int a, int b);

/// The innovations of d (zero-mean, stationary, autocovariances gamma_0 .. gamma_{m-1}) by the
/// Durbin-Levinson recursion (Brockwell & Davis 1991, 5.2), each divided by its standard
/// deviation: L^-1 d with L L^T the Toeplitz covariance. False when it is not positive definite
/// to working precision.
bool WhitenedInnovations(const std::vector<double>& d, const std::vector<double>& gamma,
                         std::vector<double>* e);

/// The check on the residual of the deterministic fit and the stochastic model fitted to it.
LongTauCheck CheckLongTauTerms(const Eigen::VectorXd& residual, double sample_rate_hz,
                               const StochasticModel& model, const LongTauCheckOptions& options);

}  // namespace fogpipe::model
