// Recordings with hidden effects for the proofs of algorithms/model (`fogpipe compare`), made by
// fogpipe::simulation. The truth is read here only to build the recording and, in the tests, to
// score; the analysis (fogpipe::model) sees the rate and the aux temperature only.
//
// Effect sizes. The requirement is "each effect a few times the bias-instability floor at the tau
// where it shows". We measure exactly that (PeakAllanSignature, asserted in compare_test.cpp): the
// effect's own overlapping Allan deviation (the effect simulated alone, no noise, through
// fogpipe::allan; for the stochastic gauss_markov its closed-form expected ADEV, IEEE Std 952
// Annex C) over the noise model's Allan deviation sigma_noise(tau) (N, Q, B, K of the seed's
// truth: the floor the effect has to rise above), at the tau in [1/fs, record/8] that maximises
// the ratio. (At navigation grade the white noise dominates sigma_noise below ~0.4-9 h, so that
// floor is above the flat 0.664 B; against 0.664 B the same effects are 6-130 times.)
// A step or a warm-up moves only the Allan differences that straddle it: a step D has
// sigma^2 = D^2 (2 m^2 + 1) / (6 m (n - 2 m + 1)) (0.24 D at tau = record/8), a warm-up of
// amplitude A and time constant tau_w at most ~0.2 A sqrt(tau_w / record) (near tau = 1.3 tau_w),
// so their signatures are far below their amplitudes.
//
// Sizing rule (k drawn per (seed, effect) from its own stream; frequency, correlation time, step
// time, time constant, sign, phase and the temperature cycle are the simulator's own draws), and
// the resulting signature ratio over design seeds 1-20 / CI seeds 101-103:
//   sinusoid          0.725 W = k sigma_noise(0.371 / f0), k in [1.4, 2.2]    1.5-2.2 / 1.5-2.1
//   warmup            |A| = k sigma_noise(tau_w), k in [50, 70]               2.0-3.8 / 1.8-2.9
//   temperature       0.725 c (p-p / 2) = k sigma_noise(0.371 P), k in [3, 5] 3.6-5.9 / 4.3-5.6
//   temperature_rate  0.725 c max|dT/dt| = k sigma_noise(0.371 P), k [9, 12] 5.0-7.0 / 5.6-6.8
//   bias_step         |D| = k sqrt(2) sigma_noise(record / 8), k in [20, 26]  6.2-8.1 / 6.5-7.8
//   gauss_markov      0.62 sigma = k sigma_noise(1.89 Tc), k in [6, 10]      8.3-14.1 / 10.5-15.2
// Aux effects (AddSupplyVoltageBias, AddQuadraticTemperatureBias) are sized on their measured
// signature directly (PeakAllanSignatureOfSeries), k drawn in [3, 5] as for temperature (for the
// quadratic one, the quadratic part's signature: the part order 2 must find); their pass counts
// over design seeds 1-20 are in docs/compare.md.
// The out-of-catalog chirp (AddChirp) is sized the same way, k = 3 in its test; its verdict rates
// over design seeds 600-619 are in docs/compare.md.
//
// Why these sizes: the seed study (compare_test.cpp, HiddenEffectStudy) rescales each effect to
// a fixed signature ratio on design seeds 1-20 and scores every criterion of the proof. Pass
// counts out of 20 (inconsistent before / first suggestion / parameters / failures point at it /
// error falls 3x / consistent after):
//   sinusoid          1x: 20 20 18 20 20 19;  1.25x, 1.5x, design 1.5-2.2 (and the previous
//                     2.2-4.0): 20 20 20 20 20 19
//   warmup            1.5x: 20 20 16 20 17 18;  2x: 20 20 18 20 20 18;  2.5x: 20 20 19 20 20 18;
//                     design 2.0-3.8: 20 20 20 20 20 18
//   temperature       3x: 20 20 15 20 16 19;  design 3.6-5.9: 20 20 20 20 19 19
//   temperature_rate  previous 2.2-3.5: 20 20 15 20 20 19;  5x: 20 20 19 20 20 19;  7x and
//                     design 5.0-7.0: 20 20 20 20 20 19
//   bias_step         3x: 20 19 12 19 6 19;  5x: 20 20 18 20 18 19;  6x, 7x, design 6.2-8.1:
//                     20 20 19 20 20 19 (previous 7.8-10.8: 20 20 20 20 20 19)
//   gauss_markov      5x: 20 20 15 20 17 18;  design 8.3-14.1: 20 20 17 20 20 16
// The limiting criteria are the 10 % on a coefficient or amplitude (temperature_rate, bias_step,
// warmup, temperature) and "the error falls at least 3x" (temperature, warmup, bias_step: the
// error before must reach ~3 times the consistent level). "Consistent after" fails on seed 14
// for every effect: the seed's noise alone is a 5 % false alarm (alpha), so no size gets that
// criterion above ~95 %; warm-up also fails it on seed 8 at every size tried (error 1.64-1.65).
// Cramer-Rao bound (Whittle Fisher information sum |X(f)|^2 / (n fs S(f)) of the regressor under
// the noise PSD S: N 0.003-0.0055 deg/sqrt(h), B 0.004 deg/h, K 0.002-0.010 deg/h/sqrt(h), Q
// 0.125 arcsec; computed with numpy for this design, not a test): ordinary least squares
// is within 1.0-1.4x of the bound for the step size and the warm-up amplitude, so a generalised
// least-squares fit would gain little; the bound itself gives P(|D error| < 10 %) = 0.85-0.89 at a
// 3x step signature and 0.98-0.99 at 5x, P(|A error| < 10 %) >= 0.92 for a 2x warm-up.
// Gauss-Markov cannot meet 10 % on sigma in >= 95 % of 6 h records at any size: even observed
// without noise, SE(sigma) / sigma = sqrt(Tc / (2 T)) and SE(ln Tc) = sqrt(2 Tc / T) (AR(1) with
// phi -> 1), 2.6-8.3 % and 5-17 % for Tc in [30, 300] s, so P(both within tolerance) averages
// 0.91 over the drawn Tc (sigma alone: 0.77 at Tc = 300 s); the design sizes reach 17 of 20.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "algorithms/model/compare.h"
#include "algorithms/simulation/gyro_simulator.h"

namespace fogpipe::model::testing {

/// Allan deviation of the stochastic terms of `e` at tau (rad/s): sqrt(3Q^2/tau^2 + N^2/tau +
/// (2 ln2/pi) B^2 + K^2 tau/3). Truth side only, to size effects.
double NoiseAllanDeviation(const simulation::GyroErrorModel& e, double tau_s);

/// Navigation-grade options of `seed` (6 h, 10 Hz, aux temperature cycle) with `effects` added by
/// the simulator and resized as documented above.
simulation::GyroSimulatorOptions HiddenEffectOptions(std::uint64_t seed,
                                                     const std::vector<simulation::Term>& effects);

/// The peak of an effect's Allan signature against the floor: the effect's overlapping Allan
/// deviation alone (simulated without any other term and computed by fogpipe::allan; the
/// expected, closed-form one for gauss_markov) over the noise model's, NoiseAllanDeviation, at the
/// tau that maximises their ratio. Taus 10 per decade up to record / 8.
struct AllanSignature {
  double tau_s = 0;
  double effect_adev_rad_s = 0;
  double noise_adev_rad_s = 0;
  double ratio = 0;
};
AllanSignature PeakAllanSignature(const simulation::GyroSimulatorOptions& options,
                                  simulation::Term effect);

/// Multiplies the size (amplitude, sigma, coefficient, step size) of the last `effect` by factor.
void ScaleEffect(simulation::Term effect, double factor, simulation::GyroSimulatorOptions* options);

/// A simulated recording and the analysis input pointing at it.
struct HiddenCase {
  simulation::SimulatedRecording recording;
  CompareInput input;
};
HiddenCase MakeHiddenCase(std::uint64_t seed, const std::vector<simulation::Term>& effects);
HiddenCase MakeHiddenCase(const simulation::GyroSimulatorOptions& options);

/// Adds to the recording's rate a narrow band of vibration outside the catalog: white noise
/// through a lightly damped second-order resonance (centre f0 Hz, damping ratio zeta; half-power
/// bandwidth 2 zeta f0, equivalent noise bandwidth pi zeta f0), scaled so that its peak one-sided
/// PSD is `peak_ratio` times the white-noise floor 2 N^2 of the truth. Its own random stream
/// (seed). The input keeps pointing at the recording's rate.
void AddNarrowBand(double f0_hz, double zeta, double peak_ratio, std::uint64_t seed, HiddenCase* c);

/// Adds a bias that follows an aux channel "pressure" (hPa; a
/// first-order Gauss-Markov wander with a 600 s correlation time, standardised: ~36 independent
/// excursions in 6 h, so neither a cycle, a step nor a warm-up fits it) with rms amplitude k times
/// the noise model's Allan deviation at 1000 s, and the channel itself to the input's aux. Its
/// own random stream (seed).
void AddPressureBias(double k, std::uint64_t seed, HiddenCase* c);

/// A vibration line that sweeps in frequency (a chirp: rotating machinery whose speed drifts
/// through the run, e.g. a pump or fan spinning up): A sin(phase), its frequency going linearly
/// from f1 to f2 over the record (f1 drawn in [0.8, 1.6] Hz, f2 = f1 + 1 Hz, a random phase), with
/// A sized so that its peak Allan signature (PeakAllanSignatureOfSeries) is k. Spread over the
/// sweep, its one-sided PSD is a plateau A^2 / (2 (f2 - f1)) across [f1, f2]: no single damped
/// resonance (narrow_band) or tone (sinusoid) has that shape. Its own random stream (seed).
struct Chirp {
  double f1_hz = 0, f2_hz = 0, amplitude_rad_s = 0;
};
Chirp AddChirp(double k, std::uint64_t seed, HiddenCase* c);

/// The peak Allan signature (as PeakAllanSignature: same taus, estimator and floor) of a rate
/// effect given as a series (rad/s) at fs, against the noise of `errors`.
AllanSignature PeakAllanSignatureOfSeries(const Eigen::VectorXd& effect_rad_s, double fs,
                                          const simulation::GyroErrorModel& errors);

/// An aux channel's true value and what the recording holds (true + sensor noise).
struct AuxSignal {
  Eigen::VectorXd truth, recorded;
};
/// supply_voltage, V: 28 V + a first-order Gauss-Markov wander (correlation time 1800 s, 0.1 V
/// rms: a bus loaded by slowly changing consumers) + a ripple of 0.03 V amplitude with a period
/// drawn in [120, 600] s and a random phase (a switching regulator's low-frequency beat), recorded
/// with 1 mV white sensor noise. Its own random stream (seed).
AuxSignal SupplyVoltage(std::uint64_t seed, long n, double fs);
/// magnetic_field, uT: 48 uT + a Gauss-Markov wander (correlation time 900 s, 0.4 uT rms),
/// recorded with 0.02 uT white sensor noise. Its own random stream (seed).
AuxSignal MagneticField(std::uint64_t seed, long n, double fs);

/// Adds the channels supply_voltage and magnetic_field to the input; the rate follows neither
/// (with the recording's temperature: three innocent channels).
void AddInnocentAux(std::uint64_t seed, HiddenCase* c);

/// Adds a bias c (V - mean V) that follows the true supply voltage, c (rad/s/V, random sign) sized
/// so that the bias' peak Allan signature (PeakAllanSignatureOfSeries) is k; the recorded
/// supply_voltage and an innocent magnetic_field go to the input. Returns c.
double AddSupplyVoltageBias(double k, std::uint64_t seed, HiddenCase* c);

/// Adds a bias c1 x + c2 x^2 with x = T - mean T of the recorded temperature and c2 = c1 / (p-p/2)
/// (at the cycle's extremes the quadratic part is as large as the linear one), sized so that the
/// quadratic part's peak Allan signature is k (random sign): the part that order 2 must detect.
/// Returns {c1 rad/s/degC, c2 rad/s/degC^2}.
std::pair<double, double> AddQuadraticTemperatureBias(double k, std::uint64_t seed, HiddenCase* c);

/// Adds a thermal hysteresis: a bias +a while the recorded temperature rises and -a while it falls
/// (heating against cooling), the direction taken from the difference of the 120 s means after
/// and before each sample (no dead band: an independent construction from the aux_hysteresis
/// regressor's, deterministic_fit.h), a > 0 sized so that its peak Allan signature
/// (PeakAllanSignatureOfSeries) is k. Returns a, rad/s.
double AddThermalHysteresis(double k, HiddenCase* c);

/// Piecewise-constant bias: the times (s) and sizes (rad/s) of its jumps, in time order.
struct BiasLevels {
  std::vector<double> step_time_s, step_size_rad_s;
};
/// Adds 3-5 bias steps (count drawn uniformly) at times drawn uniformly in [0.05, 0.95] of the
/// record, at least record / 20 apart, each of size U(0.6, 1.4) in units of their common scale
/// and a random sign, the scale sized so that the whole piecewise-constant bias' peak Allan
/// signature (PeakAllanSignatureOfSeries) is k. Its own random stream (seed).
BiasLevels AddBiasSteps(double k, std::uint64_t seed, HiddenCase* c);
/// Adds random telegraph switching: a bias that jumps between two levels +-a/2 with
/// exponentially distributed dwell times of mean dwell_s in both states (a symmetric two-state
/// Markov chain, random first state), a sized so that its peak Allan signature is k. Its
/// Lorentzian spectrum is that of a Gauss-Markov process of sigma a / 2 and correlation time
/// dwell_s / 2. Its own random stream (seed).
BiasLevels AddTelegraph(double k, double dwell_s, std::uint64_t seed, HiddenCase* c);

/// The analysis' name of a simulator term (same catalog names).
Term AnalysisTerm(simulation::Term t);

}  // namespace fogpipe::model::testing
