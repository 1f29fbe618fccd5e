// The catalog of gyro-model terms (issue 4): fixed names shared by the CLI, model files, JSON and
// HDF5. measured rate = bias + deterministic effects + stochastic terms.
//
// Stochastic terms are fitted on the Allan variance of what the deterministic part leaves (IEEE Std
// 952-1997 Annex C). Deterministic terms are fitted jointly by least squares on the rate.
// `sinusoid` is listed as stochastic in the catalog (a line of unknown phase), but fogpipe
// estimates it as a deterministic line (frequency, cosine and sine amplitude): with a fixed
// frequency that is the maximum-likelihood estimate of a line in broadband noise, and it lets the
// line be subtracted before the stochastic fit (compensate.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace fogpipe::model {

enum class Term {
  kWhite,            ///< angle random walk N
  kQuantization,     ///< Q
  kBiasInstability,  ///< B
  kRateRandomWalk,   ///< K
  kRateRamp,         ///< R
  kGaussMarkov,      ///< sigma, correlation time
  kSinusoid,         ///< frequency, amplitude (may appear more than once)
  kTemperature,      ///< bias proportional to T - T_ref (needs aux temperature)
  kTemperatureRate,  ///< bias proportional to dT/dt, Shupe effect (needs aux temperature)
  kBiasStep,         ///< time and size of a jump
  kWarmup,           ///< amplitude and time constant of the start-up transient
};

/// Lower-case catalog name, e.g. "temperature_rate".
const char* ToString(Term term);
/// Parses a catalog name; nullopt for anything else.
std::optional<Term> ParseTerm(const std::string& name);
/// Every term of the catalog, in catalog order.
const std::vector<Term>& CatalogTerms();
/// True for the terms fitted by least squares on the rate (incl. sinusoid, see above).
bool IsFittedOnRate(Term term);
/// True for the terms that need the aux channel `temperature`.
bool NeedsTemperature(Term term);
/// bias + white + quantization + bias_instability + rate_random_walk + rate_ramp (bias is
/// implicit).
std::vector<Term> DefaultTerms();
/// Parses "a,b,c". Returns false and fills *error on an unknown name.
bool ParseTermList(const std::string& text, std::vector<Term>* terms, std::string* error);

}  // namespace fogpipe::model
