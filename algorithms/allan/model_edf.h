// Confidence intervals of an OADEV table from its fitted noise model.
//
// Noise identification (noise_id.h) gives each tau one power law, and Greenhall's EDF (edf.h) is
// that law's. Where two terms of comparable size overlap, the estimate's distribution is that of
// their sum: at the crossover of white angle noise (Q) and angle random walk (N) of a navigation
// gyro the EDF of the sum lies above white FM's, which the identification picks, and the intervals
// there are too wide (docs/allan-statistics.md). The fitted five-term model gives the EDF of the
// sum directly, by the same definition Greenhall & Riley's algorithm evaluates for one law:
//   edf = 2 E[s2]^2 / Var(s2),
// with E[s2] the model Allan variance (noise_fit.h) and Var(s2) the model covariance of the
// overlapping Allan variance at that tau (avar_covariance.h: exact for Gaussian noise made of the
// IEEE terms, sampled as fogpipe samples the angle). For a single term it is that term's
// sampled-phase EDF.
//
// The model is used only where it describes the data: an OADEV table made with the calibrated
// noise-identification rule (Stable32's rule keeps Stable32's bounds), a generalised fit whose
// chi-square test does not reject the model (p >= min_p_value, no model discrepancy added), and
// rows inside the fitted tau range and outside every misfit range. Every other row keeps the EDF
// of its identified type, and edf_source says which each row has. Real gyros, whose curves
// usually reject the five-term model, keep the identification's intervals. With fewer than
// kLawBelowAverages averages, where the model's frequency noises carry the row, the bounds come
// from the estimate's law for the model (estimate_law.h) rather than chi-square with the EDF.
#pragma once

#include <string>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/noise_fit.h"

namespace fogpipe::allan {

struct ModelEdfOptions {
  /// Smallest p-value of the fit's chi-square test at which the model's EDF is used. Default 1e-3,
  /// NoiseFitOptions::discrepancy_below_p's default: below it the fit itself calls the model
  /// rejected.
  double min_p_value = 1e-3;
  /// Two-sided level of the bounds; the table's own (AllanOptions::confidence). Default 0.683.
  double confidence = 0.683;

  bool IsValid(std::string* error) const;
};

/// Replaces edf, ci_low and ci_high of the rows where the model applies (file comment) with the
/// model's, sets their edf_source to kModel, and returns how many rows changed. `fit` must be
/// FitNoiseTerms of `table`. Invalid options change nothing and return -1.
int ApplyModelEdf(const NoiseFitResult& fit, const ModelEdfOptions& options, AllanTable* table);

/// The fit and the intervals every command shows: FitNoiseTerms of `table`, then ApplyModelEdf on
/// it at `confidence` (the table's AllanOptions::confidence).
NoiseFitResult FitNoiseTermsAndModelEdf(const NoiseFitOptions& options, double confidence,
                                        AllanTable* table);

/// The model EDF of one OADEV row: averaging factor m, `count` overlapping differences, sample
/// period t0 [s], for the amplitudes of `terms` (NaN amplitudes count as 0). NaN when the model
/// variance is zero.
double ModelOverlappingAllanEdf(const NoiseTerms& terms, long long m, long long count,
                                double sample_period_s);

}  // namespace fogpipe::allan
