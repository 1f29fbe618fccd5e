#include "algorithms/common/catalog.h"

namespace fogpipe::catalog {

const std::vector<Term>& AllTerms() {
  static const std::vector<Term> kAll = {
      Term::kWhite,          Term::kQuantization, Term::kAngleQuantizer,  Term::kBiasInstability,
      Term::kRateRandomWalk, Term::kRateRamp,     Term::kGaussMarkov,     Term::kSinusoid,
      Term::kNarrowBand,     Term::kTemperature,  Term::kTemperatureRate, Term::kBiasStep,
      Term::kBiasLevels,     Term::kWarmup};
  return kAll;
}

const char* ToString(Term term) {
  switch (term) {
    case Term::kWhite:
      return "white";
    case Term::kQuantization:
      return "quantization";
    case Term::kBiasInstability:
      return "bias_instability";
    case Term::kRateRandomWalk:
      return "rate_random_walk";
    case Term::kRateRamp:
      return "rate_ramp";
    case Term::kGaussMarkov:
      return "gauss_markov";
    case Term::kSinusoid:
      return "sinusoid";
    case Term::kNarrowBand:
      return "narrow_band";
    case Term::kAngleQuantizer:
      return "angle_quantizer";
    case Term::kTemperature:
      return "temperature";
    case Term::kTemperatureRate:
      return "temperature_rate";
    case Term::kBiasStep:
      return "bias_step";
    case Term::kBiasLevels:
      return "bias_levels";
    case Term::kWarmup:
      return "warmup";
  }
  return "unknown";
}

std::optional<Term> ParseTerm(std::string_view name) {
  for (Term term : AllTerms()) {
    if (name == ToString(term)) return term;
  }
  return std::nullopt;
}

TermKind KindOf(Term term) {
  switch (term) {
    case Term::kTemperature:
    case Term::kTemperatureRate:
    case Term::kBiasStep:
    case Term::kBiasLevels:
    case Term::kWarmup:
      return TermKind::kDeterministic;
    default:
      return TermKind::kStochastic;
  }
}

bool NeedsTemperature(Term term) {
  return term == Term::kTemperature || term == Term::kTemperatureRate;
}

}  // namespace fogpipe::catalog
