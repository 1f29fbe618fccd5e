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
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/catalog.h"

namespace fogpipe::model {

using catalog::NeedsTemperature;
using catalog::ParseTerm;
using catalog::Term;
using catalog::ToString;
/// Every term of the catalog, in catalog order.
inline const std::vector<Term>& CatalogTerms() { return catalog::AllTerms(); }
/// True for the terms fitted by least squares on the rate (incl. sinusoid, see above).
bool IsFittedOnRate(Term term);
/// bias + white + quantization + bias_instability + rate_random_walk + rate_ramp (bias is
/// implicit).
std::vector<Term> DefaultTerms();
/// Parses "a,b,c". Returns false and fills *error on an unknown name.
bool ParseTermList(const std::string& text, std::vector<Term>* terms, std::string* error);

}  // namespace fogpipe::model
