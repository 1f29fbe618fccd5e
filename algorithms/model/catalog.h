// The catalog of gyro-model terms of `fogpipe compare`: fixed names shared by the CLI, model files,
// JSON and HDF5, so that a term means the same thing wherever it is written or read.
// Measured rate = bias + deterministic effects + stochastic terms.
//
// Stochastic terms are fitted on the Allan variance of what the deterministic part leaves (IEEE Std
// 952-1997 Annex C). Deterministic terms are fitted jointly by least squares on the rate.
// `sinusoid` is listed as stochastic in the catalog (a line of unknown phase), but fogpipe
// estimates it as a deterministic line (frequency, cosine and sine amplitude): with a fixed
// frequency that is the maximum-likelihood estimate of a line in broadband noise, and it lets the
// line be subtracted before the stochastic fit (compensate.h).
//
// Aux terms. Besides the fixed catalog (algorithms/common/catalog.h, shared with the simulator),
// the model has one family of terms per aux channel /aux/<name> of the recording (input contract
// v1), named after the channel:
//   aux:<name>       bias polynomial in the channel's value, sum_k c_k (x - x_ref)^k, x_ref the
//                    record's mean, order k = 1..3 chosen by BIC (deterministic_fit.h);
//   aux_rate:<name>  bias proportional to the smoothed derivative dx/dt;
//   aux_hysteresis:<name>  bias c h(t), h = +1 while the channel rises and -1 while it falls
//                    (thermal hysteresis for the temperature: heating against cooling), decided
//                    from the smoothed derivative with a dead band (deterministic_fit.h);
//   aux_am:<name>    a line whose amplitude follows the channel (amplitude modulation),
//                    (a0 + a1 (x - x_ref)) sin(2 pi f t + phi), x_ref the record's mean; linear in
//                    four coefficients at a given f, which is found as the sinusoid's is
//                    (deterministic_fit.h).
// They are not in the shared catalog because their names depend on the recording, and the
// simulator has no aux channel but the temperature. `temperature` and `temperature_rate` keep their
// names, parameters and numbers (model files written before aux terms read the same): for the
// channel "temperature" they are the linear and rate terms, aux:temperature adds orders 2-3 to
// them as one polynomial, and aux_rate:temperature is temperature_rate under another name.
// aux_hysteresis:temperature has no catalog alias (no temperature_hysteresis): the catalog names
// exist for the simulator and for model files older than aux terms, and a hysteresis term has
// neither, so it keeps the one name.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/common/catalog.h"

namespace fogpipe::model {

using catalog::NeedsTemperature;
using catalog::ParseTerm;
using catalog::Term;
using catalog::ToString;

/// What an aux term is a function of (kNone: a fixed catalog term).
enum class AuxForm { kNone, kValue, kRate, kHysteresis, kAm };

/// One term of a model: a fixed catalog term, or an aux term on a named channel.
struct ModelTerm {
  Term term = Term::kWhite;  ///< the catalog term (aux == kNone only)
  AuxForm aux = AuxForm::kNone;
  std::string channel;  ///< aux terms: the /aux/<name> channel; empty otherwise
  ModelTerm() = default;
  ModelTerm(Term catalog_term) : term(catalog_term) {}  // NOLINT: a catalog term is a model term
  static ModelTerm Aux(AuxForm form, std::string channel_name);
  bool IsAux() const { return aux != AuxForm::kNone; }
};
bool operator==(const ModelTerm& lhs, const ModelTerm& rhs);
inline bool operator!=(const ModelTerm& lhs, const ModelTerm& rhs) { return !(lhs == rhs); }

/// "white", ..., "aux:supply_voltage", "aux_rate:supply_voltage", "aux_hysteresis:temperature",
/// "aux_am:temperature".
std::string ToString(const ModelTerm& term);
/// Parses a catalog name or "aux:<channel>" / "aux_rate:<channel>" / "aux_hysteresis:<channel>" /
/// "aux_am:<channel>"; nullopt for anything else.
std::optional<ModelTerm> ParseModelTerm(std::string_view name);

/// Every term of the fixed catalog, in catalog order.
inline const std::vector<Term>& CatalogTerms() { return catalog::AllTerms(); }
/// True for the terms fitted by least squares on the rate (incl. sinusoid, see above; every aux
/// term).
bool IsFittedOnRate(const ModelTerm& term);
/// True for the terms that are a line at a fitted frequency: sinusoid and aux_am.
bool IsLine(const ModelTerm& term);
/// The aux channel a term reads ("temperature" for the thermal terms), "" for none.
std::string AuxChannelOf(const ModelTerm& term);
/// True when the term reads the channel's smoothed derivative (temperature_rate, aux_rate,
/// aux_hysteresis: the sign of it).
bool UsesDerivative(const ModelTerm& term);
/// The fixed-catalog term that an aux term of the temperature channel holds: aux:temperature
/// contains temperature (its linear coefficient), aux_rate:temperature is temperature_rate (the
/// same smoothed derivative); nullopt for every other term. A model has at most one of each pair:
/// both would make the least-squares design singular.
std::optional<Term> ThermalTermWithin(const ModelTerm& term);
/// The fixed-catalog terms of a model, in its order (its aux terms left out).
std::vector<Term> CatalogTermsOf(const std::vector<ModelTerm>& terms);
/// bias + white + quantization + bias_instability + rate_random_walk + rate_ramp (bias is
/// implicit).
std::vector<ModelTerm> DefaultTerms();
/// Parses "a,b,c". Returns false and fills *error on an unknown name.
bool ParseTermList(const std::string& text, std::vector<ModelTerm>* terms, std::string* error);

}  // namespace fogpipe::model
