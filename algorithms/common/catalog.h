// The catalog of gyro error terms. The names are fixed and shared by the CLI, configuration files,
// JSON and HDF5, so that a file written by one command is read the same way by every other:
// measured rate = bias + deterministic effects + stochastic terms.
// One list for the whole project: the simulator (algorithms/simulation) and the model fitting
// (algorithms/model) both use it. It holds names and kinds only, no estimation logic.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace fogpipe::catalog {

enum class Term {
  kWhite,            ///< angle random walk N (white rate noise), IEEE Std 952-1997 C.1.
  kQuantization,     ///< angle quantization Q.
  kBiasInstability,  ///< bias instability B (flicker rate noise).
  kRateRandomWalk,   ///< rate random walk K.
  kRateRamp,         ///< rate ramp R.
  kGaussMarkov,      ///< first-order Gauss-Markov (sigma, correlation time Tc).
  kSinusoid,         ///< sinusoidal rate (frequency f0, amplitude W); more than one allowed.
  kTemperature,      ///< bias proportional to T - T_ref; needs an aux temperature.
  kTemperatureRate,  ///< bias proportional to dT/dt (Shupe effect); needs an aux temperature.
  kBiasStep,         ///< a jump of the bias at a time.
  kWarmup,           ///< start-up transient A exp(-t/tau).
  // The values seed the simulator's and the tests' random streams: new terms go last.
  kNarrowBand,      ///< vibration band: noise through a damped resonance (f0, zeta, rms); more than
                    ///< one allowed. Fitted by compare; not made by the simulator.
  kAngleQuantizer,  ///< coarse angle counter (step q): its error replaced by a draw of the angle
                    ///< on the lattice (algorithms/model/angle_quantizer.h). Fitted by compare;
                    ///< the simulator makes it with its quantizer option, not as a term.
  kBiasLevels,  ///< piecewise-constant bias: k >= 2 jumps (times, sizes), k chosen by BIC; random
                ///< telegraph switching is its two-level case. Fitted by compare; not made by the
                ///< simulator.
};

enum class TermKind { kStochastic, kDeterministic };

/// Every term, in catalog order (narrow_band after sinusoid, angle_quantizer after quantization,
/// not in enum order).
const std::vector<Term>& AllTerms();
/// The catalog name, e.g. "bias_instability".
const char* ToString(Term term);
/// Parses a catalog name; nullopt for anything else.
std::optional<Term> ParseTerm(std::string_view name);
TermKind KindOf(Term term);
/// True for the terms that need an aux temperature channel.
bool NeedsTemperature(Term term);

}  // namespace fogpipe::catalog
