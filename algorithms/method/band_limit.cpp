#include "algorithms/method/band_limit.h"

#include <algorithm>
#include <vector>

#include "algorithms/filters/butterworth.h"

namespace fogpipe::method {

bool BandLimitOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (!(cutoff_ratio >= 0.0 && cutoff_ratio <= 1.0))
    return fail("band_limit.cutoff_ratio must be in [0, 1]");
  if (order != 2 && order != 4) return fail("band_limit.order must be 2 or 4");
  if (!(min_cycles >= 1.0)) return fail("band_limit.min_cycles must be >= 1");
  return true;
}

void BandLimitImfs(const BandLimitOptions& options, emd::EmdResult* d) {
  if (!(options.cutoff_ratio > 0.0)) return;
  const Eigen::Index n = d->residue.size();
  const int count = static_cast<int>(d->imfs.size());
  std::vector<double> work;  // reused by every split (fresh pages are slow)
  Eigen::VectorXd leak;
  for (int k = 0; k < count; ++k) {
    // The band of the component as it stands, the previous one's leakage included.
    emd::DescribeImf(d->imfs[k], &d->imf_info[k]);
    const double period = d->imf_info[k].mean_period_samples;
    if (!(period > 0.0) || static_cast<double>(n) / period < options.min_cycles) continue;
    const double cutoff = options.cutoff_ratio / period;  // cycles per sample
    if (!(cutoff < 0.45)) continue;  // below the Nyquist band edge with room for the design
    // The odd-reflection pad of the low-pass, at most the record: the slowest IMFs' cutoffs have
    // periods near the record length, and a longer pad only repeats the record.
    const Eigen::Index pad = std::min<Eigen::Index>(filters::ButterworthPad(cutoff, 1.0), n - 1);
    filters::FilterForwardBackward(filters::ButterworthSections(options.order, cutoff, 1.0),
                                   d->imfs[k], pad, &work, &leak);
    d->imfs[k] -= leak;
    emd::DescribeImf(d->imfs[k], &d->imf_info[k]);
    if (k + 1 < count) {
      d->imfs[k + 1] += leak;
    } else {
      d->residue += leak;
    }
  }
}

}  // namespace fogpipe::method
