// How every command shows the IEEE noise-term fit (allan::FitNoiseTerms): the terms with their
// standard errors, significance and slope read-offs, the goodness of fit (chi2/dof, p-value, tau
// ranges the model misses) and the per-term reliability flags with their reasons. One rendering,
// so that `allan`, `info`, `compare` and the campaign table say the same thing.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "algorithms/allan/noise_fit.h"

namespace fogpipe::io {

/// The terms table (engineer's units, units in every row), then goodness of fit and flags.
void PrintNoiseFitText(std::ostream& out, const allan::NoiseFitResult& fit);

/// Per term {"symbol", "z", "significant", "upper_limit" (engineer's unit), "unit",
/// "readoff" (engineer's unit), "reliable", "reason"}.
nlohmann::json NoiseFitAssessmentJson(const allan::NoiseFitResult& fit);

/// One line: "chi2/dof 1.05 (p 0.39)" plus ", unreliable: B (model does not describe ...)" for
/// each flagged term; "ok" parts are omitted. For summaries and table cells.
std::string NoiseFitFlagLine(const allan::NoiseFitResult& fit);

/// "B,K" — the symbols of the unreliable terms, "" when none.
std::string UnreliableTermSymbols(const allan::NoiseFitResult& fit);

/// The cross-check of the identified noise types: "noise types: alpha equals the fitted model's
/// dominant term (allan::ModelDominantAlpha) at 14 of 17 taus; differs at 0.1-0.3 s", one line.
std::string NoiseTypeCrossCheckLine(const allan::AllanTable& table,
                                    const allan::NoiseFitResult& fit);

}  // namespace fogpipe::io
