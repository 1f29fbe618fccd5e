// Band-limited components: EMD's IMFs with each one's leakage below its band moved to the next.
//
// Why: the IMFs of a noisy record are not orthogonal. Sifting builds each IMF from envelope means
// that are only approximately its local mean, so an IMF carries content far below its own band
// that the slower IMFs carry with the opposite sign (on white noise the sum of the IMFs' Allan
// variances is 1.7-2.7x the record's at long tau). A filter per IMF that removes a noise-dominated
// IMF then removes that leakage too, and what it cancelled in the slower IMFs reappears: the
// paper's method 1 raised the long-tau Allan deviation above the raw one on static records
// (docs/filtering.md), and on moving truth a step or ramp that EMD spreads over several IMFs lost
// parts of itself.
//
// What: in order k = 1..K, the part of IMF k below cutoff_ratio / T_k cycles per sample (T_k its
// mean period) is taken out by a zero-phase Butterworth low-pass (filters/butterworth.h) and added
// to IMF k + 1 (the last IMF's to the residue), whose own split then sees it. The sum of the
// components is unchanged (to rounding), each component holds its band only, and content below a
// band is judged, modelled and filtered with the band it belongs to. The AR models and Kalman
// filters of method 1 then run on these components (method.h). IMFs with fewer than min_cycles
// cycles per record are left as they are (their band reaches the record length).
//
// The ratio 0.7 (the cutoff 0.7 / T_k, half an octave below the IMF's mean frequency, where a
// dyadic filter bank's neighbour begins) was chosen on design records (simulate --profile paper
// and nav seeds 5000+ and 7000+, moving-truth seeds 1-5) among 0.35, 0.5, 0.7 and 1.0;
// docs/filtering.md gives the measurements.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/emd/emd.h"

namespace fogpipe::method {

struct BandLimitOptions {
  /// Leakage below cutoff_ratio / T_k cycles per sample moves from IMF k to IMF k + 1. 0: the
  /// IMFs are left as EMD made them (the paper's method). Default 0.7; must be in [0, 1].
  double cutoff_ratio = 0.7;
  /// Order of each pass of the zero-phase Butterworth low-pass: 2 or 4. Default 4.
  int order = 4;
  /// IMFs with fewer cycles per record (N / T_k) are left as they are. Default 2.
  double min_cycles = 2.0;

  bool IsValid(std::string* error) const;
};

/// The split above one IMF at a time, as EMD extracts them (emd::ImfSink): the IMFs can be
/// modelled and released one by one. Memory: two vectors of N doubles (the pending leakage and
/// the low-pass work) besides the IMF.
class BandLimiter {
 public:
  explicit BandLimiter(const BandLimitOptions& options) : options_(options) {}
  /// IMF k as EMD made it, with its info; IMFs come in order k = 0, 1, ... The previous IMF's
  /// leakage is added, this one's removed (and kept for the next): *imf and *info then describe
  /// the component as modelled and stored.
  void Next(Eigen::VectorXd* imf, emd::ImfInfo* info);
  /// Adds the last IMF's leakage to the residue and releases the buffers (no Next after it).
  void Finish(Eigen::VectorXd* residue);

 private:
  BandLimitOptions options_;
  std::vector<double> work_;  // reused by every split (fresh pages are slow)
  Eigen::VectorXd leak_;
  bool pending_ = false;
};

/// Applies the split above to d->imfs (in place; the residue receives the last IMF's leakage).
/// Each component's cutoff uses its mean period as it stands when split (the previous
/// component's leakage included); d->imf_info's shape fields (mean period, energy, extrema, zero
/// crossings) then describe the components as stored (emd::DescribeImf). Does nothing when
/// options.cutoff_ratio is 0.
void BandLimitImfs(const BandLimitOptions& options, emd::EmdResult* d);

}  // namespace fogpipe::method
