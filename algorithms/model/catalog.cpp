#include "algorithms/model/catalog.h"

#include <sstream>

namespace fogpipe::model {

bool IsFittedOnRate(Term term) {
  return term == Term::kSinusoid || term == Term::kTemperature || term == Term::kTemperatureRate ||
         term == Term::kBiasStep || term == Term::kWarmup;
}

std::vector<Term> DefaultTerms() {
  return {Term::kWhite, Term::kQuantization, Term::kBiasInstability, Term::kRateRandomWalk,
          Term::kRateRamp};
}

bool ParseTermList(const std::string& text, std::vector<Term>* terms, std::string* error) {
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (item.empty() || item == "bias") continue;  // bias is always in the model
    auto term = ParseTerm(item);
    if (!term) {
      if (error) *error = "unknown term '" + item + "'";
      return false;
    }
    terms->push_back(*term);
  }
  return true;
}

}  // namespace fogpipe::model
