#include "algorithms/model/catalog.h"

#include <sstream>

namespace fogpipe::model {
namespace {

constexpr std::string_view kAuxPrefix = "aux:";
constexpr std::string_view kAuxRatePrefix = "aux_rate:";
constexpr std::string_view kAuxHysteresisPrefix = "aux_hysteresis:";
constexpr std::string_view kAuxAmPrefix = "aux_am:";

// A channel name as input contract v1 allows it under /aux: non-empty, no '/' and no ','
// (the term list separator).
bool ValidChannel(std::string_view name) {
  return !name.empty() && name.find_first_of("/,") == std::string_view::npos;
}

}  // namespace

ModelTerm ModelTerm::Aux(AuxForm form, std::string channel_name) {
  ModelTerm term;
  term.aux = form;
  term.channel = std::move(channel_name);
  return term;
}

bool operator==(const ModelTerm& lhs, const ModelTerm& rhs) {
  if (lhs.aux != rhs.aux) return false;
  return lhs.IsAux() ? lhs.channel == rhs.channel : lhs.term == rhs.term;
}

std::string ToString(const ModelTerm& term) {
  switch (term.aux) {
    case AuxForm::kValue:
      return std::string(kAuxPrefix) + term.channel;
    case AuxForm::kRate:
      return std::string(kAuxRatePrefix) + term.channel;
    case AuxForm::kHysteresis:
      return std::string(kAuxHysteresisPrefix) + term.channel;
    case AuxForm::kAm:
      return std::string(kAuxAmPrefix) + term.channel;
    case AuxForm::kNone:
      break;
  }
  return ToString(term.term);
}

std::optional<ModelTerm> ParseModelTerm(std::string_view name) {
  for (auto [prefix, form] :
       {std::make_pair(kAuxPrefix, AuxForm::kValue), std::make_pair(kAuxRatePrefix, AuxForm::kRate),
        std::make_pair(kAuxHysteresisPrefix, AuxForm::kHysteresis),
        std::make_pair(kAuxAmPrefix, AuxForm::kAm)}) {
    if (name.substr(0, prefix.size()) != prefix) continue;
    const std::string_view channel = name.substr(prefix.size());
    if (!ValidChannel(channel)) return std::nullopt;
    return ModelTerm::Aux(form, std::string(channel));
  }
  const auto term = ParseTerm(name);
  if (!term) return std::nullopt;
  return ModelTerm(*term);
}

bool IsFittedOnRate(const ModelTerm& term) {
  if (term.IsAux()) return true;
  return term.term == Term::kSinusoid || term.term == Term::kTemperature ||
         term.term == Term::kTemperatureRate || term.term == Term::kBiasStep ||
         term.term == Term::kBiasLevels || term.term == Term::kWarmup;
}

bool IsLine(const ModelTerm& term) {
  return term.IsAux() ? term.aux == AuxForm::kAm : term.term == Term::kSinusoid;
}

std::string AuxChannelOf(const ModelTerm& term) {
  if (term.IsAux()) return term.channel;
  return NeedsTemperature(term.term) ? "temperature" : "";
}

bool UsesDerivative(const ModelTerm& term) {
  return term.IsAux() ? term.aux == AuxForm::kRate || term.aux == AuxForm::kHysteresis
                      : term.term == Term::kTemperatureRate;
}

std::vector<ModelTerm> DefaultTerms() {
  return {Term::kWhite, Term::kQuantization, Term::kBiasInstability, Term::kRateRandomWalk,
          Term::kRateRamp};
}

bool ParseTermList(const std::string& text, std::vector<ModelTerm>* terms, std::string* error) {
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (item.empty() || item == "bias") continue;  // bias is always in the model
    auto term = ParseModelTerm(item);
    if (!term) {
      if (error) {
        *error = "unknown term '" + item + "'";
        if (item == "aux" || item == "aux_rate" || item == "aux_hysteresis" || item == "aux_am")
          *error += " (aux terms name their channel: " + item + ":<channel>)";
      }
      return false;
    }
    terms->push_back(*term);
  }
  return true;
}

std::optional<Term> ThermalTermWithin(const ModelTerm& term) {
  if (!term.IsAux() || term.channel != "temperature" || term.aux == AuxForm::kHysteresis ||
      term.aux == AuxForm::kAm)
    return std::nullopt;
  return term.aux == AuxForm::kRate ? Term::kTemperatureRate : Term::kTemperature;
}

std::vector<Term> CatalogTermsOf(const std::vector<ModelTerm>& terms) {
  std::vector<Term> catalog_terms;
  for (const ModelTerm& term : terms)
    if (!term.IsAux()) catalog_terms.push_back(term.term);
  return catalog_terms;
}

}  // namespace fogpipe::model
