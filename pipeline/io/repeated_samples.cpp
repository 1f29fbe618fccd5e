#include "pipeline/io/repeated_samples.h"

#include <sstream>

namespace fogpipe::io {

RepeatedRunReport FindRepeatedRun(const Eigen::Ref<const Eigen::VectorXd>& x, double fill_value) {
  RepeatedRunReport r;
  const long long n = x.size();
  if (n == 0) return r;
  long long best_start = 0, best = 1, second = 0;
  long long start = 0;
  for (long long i = 1; i <= n; ++i) {
    if (i < n && x[i] == x[i - 1]) continue;
    const long long length = i - start;  // the run [start, i)
    if (length > best) {
      second = best;
      best = length;
      best_start = start;
    } else if (length > second) {
      second = length;
    }
    start = i;
  }
  r.start = best_start;
  r.samples = best;
  r.value = x[best_start];
  r.next_longest = second;
  r.at_end = best_start + best == n;
  r.equals_fill_value = r.value == fill_value;
  const double other = static_cast<double>(second);
  r.unwritten_tail = r.at_end && r.equals_fill_value && best >= kMinTailRun &&
                     static_cast<double>(best) > kTailRatio * other;
  r.stuck = best >= kMinStuckRun && static_cast<double>(best) > kStuckRatio * other;
  return r;
}

std::string DescribeRepeatedRun(const RepeatedRunReport& r, double sample_rate_hz,
                                const std::string& units) {
  if (!r.flagged()) return "";
  std::ostringstream s;
  s.precision(6);
  const double t0 = static_cast<double>(r.start) / sample_rate_hz;
  const double t1 = static_cast<double>(r.start + r.samples) / sample_rate_hz;
  s << "samples " << r.start << ".." << (r.start + r.samples - 1) << " (t = " << t0 << ".." << t1
    << " s) all equal " << r.value << " " << units << ", a run of " << r.samples
    << " samples where no other run exceeds " << r.next_longest << ": ";
  if (r.unwritten_tail) {
    s << "the end of the record holds the dataset's fill value, as storage that was never "
         "written reads (a recording cut short?)";
  } else {
    s << "a frozen output";
  }
  s << "; analysed as recorded";
  return s.str();
}

}  // namespace fogpipe::io
