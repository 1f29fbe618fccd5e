#include "algorithms/filters/reference_filters.h"

#include <atomic>
#include <functional>
#include <iterator>

namespace fogpipe::filters {
namespace {

ReferenceOutput Named(const std::string& name, const char* parameter_name, const char* units) {
  ReferenceOutput out;
  out.name = name;
  out.parameter_name = parameter_name;
  out.parameter_units = units;
  return out;
}

void RunButterworth(const Eigen::VectorXd& x, double fs, const ButterworthOptions& options,
                    ReferenceOutput* out) {
  ButterworthResult r = ZeroPhaseButterworth(x, fs, options);
  out->signal = std::move(r.output);
  out->parameter = r.cutoff_hz;
  out->termination = r.termination;
  out->message = r.message;
  if (r.at_lower_bound) out->note = "GCV chose the lowest cutoff of its range";
}

void RunMovingAverage(const Eigen::VectorXd& x, const MovingAverageOptions& options,
                      ReferenceOutput* out) {
  MovingAverageResult r = MovingAverage(x, options);
  out->signal = std::move(r.output);
  out->parameter = static_cast<double>(2 * r.half_width + 1);
  out->termination = r.termination;
  out->message = r.message;
  if (r.at_upper_bound) out->note = "GCV chose the widest window of its range";
}

void RunRandomWalk(const Eigen::VectorXd& x, const RandomWalkKalmanOptions& options,
                   ReferenceOutput* filter, ReferenceOutput* smoother) {
  RandomWalkKalmanResult r = RandomWalkKalman(x, options);
  filter->signal = std::move(r.filtered);
  smoother->signal = std::move(r.smoothed);
  for (ReferenceOutput* out : {filter, smoother}) {
    out->parameter = r.r > 0.0 ? r.q / r.r : 0.0;
    out->termination = r.termination;
    out->message = r.message;
    if (r.at_lower_bound) out->note = "ML chose the smallest q / R of its range (constant rate)";
  }
}

}  // namespace

bool ReferenceFilterOptions::IsValid(std::string* error) const {
  return butterworth.IsValid(error) && moving_average.IsValid(error) && random_walk.IsValid(error);
}

const std::vector<std::string>& ReferenceFilterNames() {
  static const std::vector<std::string> names = {"butterworth", "moving_average", "rw_kalman",
                                                 "rw_rts"};
  return names;
}

std::vector<ReferenceOutput> RunReferenceFilters(const Eigen::VectorXd& x, double sample_rate_hz,
                                                 const ReferenceFilterOptions& options,
                                                 const ForEach& for_each,
                                                 const std::function<void()>& beside) {
  if (!options.enabled) {
    if (beside) beside();
    return {};
  }
  const std::vector<std::string>& names = ReferenceFilterNames();
  std::vector<ReferenceOutput> out = {
      Named(names[0], "cutoff", "Hz"), Named(names[1], "window", "samples"),
      Named(names[2], "q_over_r", "1"), Named(names[3], "q_over_r", "1")};
  // Four tasks handed out in this order to two lanes, each lane taking the next when it is free:
  // the longest (the Butterworth's GCV, the random-walk likelihood) start first, the others fill
  // in behind them, so neither lane waits for a fixed share of the other's.
  const std::function<void()> tasks[] = {
      [&] { RunButterworth(x, sample_rate_hz, options.butterworth, &out[0]); },
      [&] { RunRandomWalk(x, options.random_walk, &out[2], &out[3]); },
      [&] { RunMovingAverage(x, options.moving_average, &out[1]); },
      [&] {
        if (beside) beside();
      }};
  constexpr int kTasks = static_cast<int>(std::size(tasks));
  std::atomic<int> next{0};
  for_each(2, [&](int) {
    for (int t = next++; t < kTasks; t = next++) tasks[t]();
  });
  return out;
}

}  // namespace fogpipe::filters
