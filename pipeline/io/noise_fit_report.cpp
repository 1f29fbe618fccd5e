#include "pipeline/io/noise_fit_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>

namespace fogpipe::io {
namespace {

std::string Format(double value, const char* format) {
  if (!std::isfinite(value)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

std::string NoiseTypeCrossCheckLine(const allan::AllanTable& table,
                                    const allan::NoiseFitResult& fit) {
  const std::vector<int> model = allan::ModelDominantAlpha(fit.terms, table.tau_s);
  int agree = 0, compared = 0;
  std::vector<allan::TauRange> differ;
  bool extending = false;
  for (size_t i = 0; i < table.size() && i < table.alpha.size(); ++i) {
    const bool identified =
        i < table.alpha_method.size() && table.alpha_method[i] != allan::NoiseIdMethod::kNone;
    if (model[i] == allan::kNoModelAlpha || !identified) {
      extending = false;
      continue;
    }
    ++compared;
    if (table.alpha[i] == model[i]) {
      ++agree;
      extending = false;
    } else if (extending) {
      differ.back().high_s = table.tau_s[i];
    } else {
      differ.push_back({table.tau_s[i], table.tau_s[i]});
      extending = true;
    }
  }
  std::string line = "noise types: alpha equals the fitted model's dominant term at " +
                     std::to_string(agree) + " of " + std::to_string(compared) + " taus";
  constexpr std::size_t kMaxRanges = 6;  // a dense grid alternates between neighbouring types
  if (!differ.empty()) {
    const std::size_t more = differ.size() > kMaxRanges ? differ.size() - kMaxRanges : 0;
    differ.resize(std::min(differ.size(), kMaxRanges));
    line += "; differs at " + allan::FormatTauRanges(differ);
    if (more > 0) line += " and " + std::to_string(more) + " more ranges";
  }
  return line;
}

void PrintNoiseFitText(std::ostream& out, const allan::NoiseFitResult& fit) {
  static const char* kNames[allan::kNoiseTermCount] = {
      "quantization", "angle random walk", "bias instability", "rate random walk", "rate ramp"};
  out << "\nNoise terms (joint non-negative " << (fit.generalized ? "generalised" : "weighted")
      << " least squares on sigma^2, IEEE Std 952-1997 Annex C; "
      << ToString(fit.summary.termination) << ", " << fit.summary.points << " points):\n";
  out << "     term                        value +- SE            unit           read-off     z  "
         "  verdict\n";
  for (int j = 0; j < allan::kNoiseTermCount; ++j) {
    const allan::TermAssessment& a = fit.assessment[j];
    const double value = allan::EngineeringValue(fit.terms, j);
    std::string verdict =
        !std::isfinite(a.z) ? ""
        : a.significant     ? "significant"
                            : "not significant (< " +
                              Format(allan::EngineeringAmplitude(j, a.upper_limit), "%.2g") + ")";
    if (!a.reliable) verdict += (verdict.empty() ? "" : ", ") + std::string("UNRELIABLE");
    out << "  " << allan::TermSymbol(j) << "  " << std::left << std::setw(18) << kNames[j]
        << std::right << std::setw(13) << Format(value, "%.4e") << " +- " << std::left
        << std::setw(10) << Format(allan::EngineeringStandardError(fit.terms, j), "%.2e")
        << std::setw(15) << allan::EngineeringUnit(j) << std::right << std::setw(10)
        << Format(allan::EngineeringValue(fit.slope_readoff, j), "%.3e") << std::setw(7)
        << Format(a.z, "%.1f") << "  " << verdict << "\n";
    if (!a.reliable) out << "       " << allan::TermSymbol(j) << ": " << a.reason << "\n";
  }
  // A check of terms fitted elsewhere (allan::AssessNoiseTerms) has no goodness of fit of its own.
  if (std::isfinite(fit.chi2))
    out << "  goodness of fit: chi2 " << Format(fit.chi2, "%.4g") << " on " << fit.dof
        << " dof, chi2/dof " << Format(fit.dof > 0 ? fit.chi2 / fit.dof : NAN, "%.3g")
        << ", p-value " << Format(fit.p_value, "%.3g") << "\n";
  if (!fit.misfit_ranges.empty())
    out << "  the model misses the curve at " << allan::FormatTauRanges(fit.misfit_ranges)
        << " (measured sigma^2 outside the model's 99.7 % interval)\n";
  if (!fit.summary.message.empty()) out << "  (" << fit.summary.message << ")\n";
}

nlohmann::json NoiseFitAssessmentJson(const allan::NoiseFitResult& fit) {
  nlohmann::json terms = nlohmann::json::array();
  for (int j = 0; j < allan::kNoiseTermCount; ++j) {
    const allan::TermAssessment& a = fit.assessment[j];
    terms.push_back({{"symbol", allan::TermSymbol(j)},
                     {"unit", allan::EngineeringUnit(j)},
                     {"z", Number(a.z)},
                     {"significant", a.significant},
                     {"upper_limit", Number(allan::EngineeringAmplitude(j, a.upper_limit))},
                     {"readoff", Number(allan::EngineeringValue(fit.slope_readoff, j))},
                     {"reliable", a.reliable},
                     {"reason", a.reason}});
  }
  return terms;
}

std::string UnreliableTermSymbols(const allan::NoiseFitResult& fit) {
  std::string s;
  for (int j = 0; j < allan::kNoiseTermCount; ++j)
    if (!fit.assessment[j].reliable)
      s += (s.empty() ? "" : ",") + std::string(allan::TermSymbol(j));
  return s;
}

std::string NoiseFitFlagLine(const allan::NoiseFitResult& fit) {
  std::string s = "chi2/dof " + Format(fit.dof > 0 ? fit.chi2 / fit.dof : NAN, "%.3g") + " (p " +
                  Format(fit.p_value, "%.2g") + ")";
  for (int j = 0; j < allan::kNoiseTermCount; ++j)
    if (!fit.assessment[j].reliable)
      s += std::string(", ") + allan::TermSymbol(j) + " unreliable: " + fit.assessment[j].reason;
  return s;
}

}  // namespace fogpipe::io
