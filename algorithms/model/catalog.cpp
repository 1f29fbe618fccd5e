#include "algorithms/model/catalog.h"

#include <sstream>

namespace fogpipe::model {

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
    case Term::kTemperature:
      return "temperature";
    case Term::kTemperatureRate:
      return "temperature_rate";
    case Term::kBiasStep:
      return "bias_step";
    case Term::kWarmup:
      return "warmup";
  }
  return "unknown";
}

const std::vector<Term>& CatalogTerms() {
  static const std::vector<Term> kAll = {
      Term::kWhite,           Term::kQuantization, Term::kBiasInstability, Term::kRateRandomWalk,
      Term::kRateRamp,        Term::kGaussMarkov,  Term::kSinusoid,        Term::kTemperature,
      Term::kTemperatureRate, Term::kBiasStep,     Term::kWarmup};
  return kAll;
}

std::optional<Term> ParseTerm(const std::string& name) {
  for (Term t : CatalogTerms()) {
    if (name == ToString(t)) return t;
  }
  return std::nullopt;
}

bool IsFittedOnRate(Term term) {
  return term == Term::kSinusoid || term == Term::kTemperature || term == Term::kTemperatureRate ||
         term == Term::kBiasStep || term == Term::kWarmup;
}

bool NeedsTemperature(Term term) {
  return term == Term::kTemperature || term == Term::kTemperatureRate;
}

std::vector<Term> DefaultTerms() {
  return {Term::kWhite, Term::kQuantization, Term::kBiasInstability, Term::kRateRandomWalk,
          Term::kRateRamp};
}

bool ParseTermList(const std::string& text, std::vector<Term>* terms, std::string* error) {
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty() || item == "bias") continue;  // bias is always in the model
    auto t = ParseTerm(item);
    if (!t) {
      if (error) *error = "unknown term '" + item + "'";
      return false;
    }
    terms->push_back(*t);
  }
  return true;
}

}  // namespace fogpipe::model
