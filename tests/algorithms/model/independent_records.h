// Recordings built in the test from written-out noise laws, independent of fogpipe::simulation,
// with the truth kept beside them: the proof of the aux_am term (compare_test.cpp) must not share
// a generator with the code under test or with the simulator the other proofs use.
//
// A record: 6 h at 10 Hz of a navigation-grade gyro (ranges as the navigation-grade draws of
// algorithms/simulation, redrawn here from the record's own stream):
//   - white rate noise N in [0.003, 0.008] deg/sqrt(h): rate samples of sd N sqrt(fs);
//   - bias instability B in [0.002, 0.006] deg/h: flicker noise, approximated by a sum of
//     first-order Gauss-Markov processes with correlation times tau_j = 10^(j/3) s, j = 0..13 (1 s
//     to 6 h), each of variance d B^2 / pi, d = ln(10) / 3 the spacing in ln tau: the one-sided
//     PSDs 4 s^2 tau / (1 + (2 pi f tau)^2) summed over log-spaced tau integrate to s^2 / (d f),
//     which is the IEEE Std 952 (Annex C) flicker law B^2 / (pi f) one-sided (B^2 / (2 pi f)
//     two-sided), so that the Allan deviation is ~0.664 B between ~10 s and ~1000 s (checked with
//     numpy: 0.64-0.67 at 10-100 s);
//   - rate random walk K in [0.002, 0.010] deg/h/sqrt(h): increments of sd K / sqrt(fs);
//   - a constant bias in [-0.05, 0.05] deg/h;
//   - an angle quantizer of step q = Q sqrt(12), Q in [0.05, 0.2] arcsec: the angle (the running
//   sum
//     of rate / fs) is rounded to multiples of q and differenced back to a rate. Dithered: a
//     uniform dither of one step is added before rounding (the error is then white, of variance
//     q^2 / 6); undithered: rounded as it is, which leaves the quantizer's periodic patterns.
// Three aux channels: temperature (degC: 25 + p-p / 2 sin(2 pi t / P + phi), p-p in [6, 12] degC,
// P in [3600, 7200] s, plus a Gauss-Markov wander of 0.2 degC, correlation time 1800 s, recorded
// with 0.005 degC white sensor noise), supply_voltage and magnetic_field (hidden_effects.h's
// SupplyVoltage and MagneticField, which are written in the test too).
//
// The AM line: (a0 + a1 (T - mean T)) sin(2 pi f t + phi) in the rate, T the true temperature, f
// log-uniform in [0.1, 3] Hz, a random phase. Its size is that of the modulation, the part the
// term must find: k = |a1| sd(T) sqrt(T_rec / S(f)), the t-statistic of a1 in noise of one-sided
// PSD S(f) near f (least squares on the column (T - mean T) sin(2 pi f t), whose sum of squares is
// n sd(T)^2 / 2, the noise near f acting as white of per-sample variance S(f) fs / 2: var(a1) =
// S(f) / (T_rec sd(T)^2)); S(f) = 2 N^2 + 8 s^2 fs sin^2(pi f / fs), the white noise and the
// dithered quantizer's white angle error (s^2 = q^2 / 6) differenced into a rate. The
// carrier a0 = |a1| (p-p / 2) / depth, the modulation depth drawn in [0.3, 0.7], a1's sign random.
// (Sized instead by a sinusoid's Allan signature, hidden_effects.h's rule, a line at 0.1-3 Hz
// against the white floor of a 6 h record is thousands of times its detection threshold.)
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "algorithms/model/compare.h"

namespace fogpipe::model::testing {

enum class Quantizer { kDithered, kUndithered };

/// The AM line's truth (SI), its reference the true temperature's mean.
struct AmLineTruth {
  double frequency_hz = 0, amplitude_rad_s = 0, phase_rad = 0;
  double modulation_rad_s_per_degc = 0, depth = 0, reference_degc = 0;
};

struct IndependentRecord {
  double fs = 10.0;
  double n_rad_sqrt_s = 0, b_rad_s = 0, k_rad_s_sqrt_s = 0, q_rad = 0, bias_rad_s = 0;
  Eigen::VectorXd rate_rad_s;
  Eigen::VectorXd temperature_truth_degc;
  std::vector<AuxChannel> aux;  ///< temperature, supply_voltage, magnetic_field (recorded)
  std::optional<AmLineTruth> am;
  /// The analysis input: points at rate_rad_s (valid while the record lives and is not moved).
  CompareInput Input() const;
};

/// Options of a record: with an AM line of signature k (> 0) or none (k = 0).
struct IndependentRecordOptions {
  Quantizer quantizer = Quantizer::kDithered;
  double am_signature = 0;
};

/// A record of `seed` (its own streams; the same seed gives the same noise, channels and line).
IndependentRecord MakeIndependentRecord(std::uint64_t seed,
                                        const IndependentRecordOptions& options);

/// sqrt(3 Q^2 / tau^2 + N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3), rad/s (IEEE Std 952 Annex C):
/// the noise floor a record's effect is sized against.
double IndependentNoiseAllanDeviation(const IndependentRecord& record, double tau_s);

}  // namespace fogpipe::model::testing
