#include "algorithms/emd/extrema.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "tests/algorithms/emd/test_signals.h"

namespace fogpipe::emd {
namespace {

struct Found {
  ExtremaCounts counts;
  std::vector<int> max_pos2, min_pos2;
};

Found Find(const std::vector<double>& x, EnvelopeKnots* maxima, EnvelopeKnots* minima) {
  Found f;
  maxima->Reserve(static_cast<int>(x.size()));
  minima->Reserve(static_cast<int>(x.size()));
  f.counts = FindExtrema(x.data(), static_cast<int>(x.size()), maxima, minima);
  for (int k = 0; k < maxima->num_interior(); ++k) f.max_pos2.push_back(maxima->interior_pos2(k));
  for (int k = 0; k < minima->num_interior(); ++k) f.min_pos2.push_back(minima->interior_pos2(k));
  return f;
}

TEST(Extrema, FindsStrictMaximaAndMinimaButNeverTheEndSamples) {
  EnvelopeKnots maxima, minima;
  //                       0    1    2    3    4    5    6
  const std::vector<double> x = {5.0, 1.0, 3.0, 2.0, 4.0, 0.0, 9.0};
  const Found f = Find(x, &maxima, &minima);
  EXPECT_EQ(f.max_pos2, (std::vector<int>{4, 8}));  // Samples 2 and 4.
  EXPECT_EQ(f.min_pos2, (std::vector<int>{2, 6, 10}));
  EXPECT_EQ(f.counts.num_maxima, 2);
  EXPECT_EQ(f.counts.num_minima, 3);
  EXPECT_DOUBLE_EQ(maxima.interior_value(1), 4.0);
  EXPECT_DOUBLE_EQ(minima.interior_value(2), 0.0);
}

TEST(Extrema, FlatRunCountsAsOneExtremumAtItsCentre) {
  EnvelopeKnots maxima, minima;
  // Maximum plateau over samples 2..4 (centre 3), minimum plateau over 6..7 (centre 6.5).
  const std::vector<double> x = {0.0, 1.0, 2.0, 2.0, 2.0, 1.0, -1.0, -1.0, 0.5, 0.0};
  const Found f = Find(x, &maxima, &minima);
  EXPECT_EQ(f.max_pos2, (std::vector<int>{6, 16}));  // 3 and 8.
  EXPECT_EQ(f.min_pos2, (std::vector<int>{13}));     // 6.5
  EXPECT_DOUBLE_EQ(maxima.interior_value(0), 2.0);
  EXPECT_DOUBLE_EQ(minima.interior_value(0), -1.0);  // Read inside the run (sample 7).
}

TEST(Extrema, StepThatKeepsRisingIsNoExtremum) {
  EnvelopeKnots maxima, minima;
  const std::vector<double> x = {0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 3.0};
  const Found f = Find(x, &maxima, &minima);
  EXPECT_EQ(f.counts.num_maxima, 0);
  EXPECT_EQ(f.counts.num_minima, 0);
}

TEST(Extrema, CountsSignChangesAndNotTouchesOfZero) {
  // Crossings: 1 -> -1 (through a zero run), -2 -> 3; touches: 3 -> 0 -> 2 is not a crossing.
  const std::vector<double> x = {1.0, 0.0, 0.0, -1.0, -2.0, 3.0, 0.0, 2.0};
  const ExtremaCounts c = FindExtrema(x.data(), static_cast<int>(x.size()), nullptr, nullptr);
  EXPECT_EQ(c.num_zero_crossings, 2);
}

TEST(Extrema, CountingAloneGivesTheSameCountsAsStoring) {
  const Eigen::VectorXd x = testing::WhiteNoise(10000, 7);
  EnvelopeKnots maxima, minima;
  maxima.Reserve(100);  // Too small on purpose: storing stops, counting does not.
  minima.Reserve(100);
  const ExtremaCounts stored = FindExtrema(x.data(), 10000, &maxima, &minima);
  const ExtremaCounts counted = FindExtrema(x.data(), 10000, nullptr, nullptr);
  EXPECT_EQ(stored.num_maxima, counted.num_maxima);
  EXPECT_EQ(stored.num_minima, counted.num_minima);
  EXPECT_EQ(stored.num_zero_crossings, counted.num_zero_crossings);
  EXPECT_EQ(maxima.num_interior(), 100);
  // A sample of white noise is a local maximum with probability 1/3 (3 exchangeable values); the
  // count over 9998 interior samples has standard deviation below sqrt(9998 * 2/9) = 47.
  EXPECT_NEAR(counted.num_maxima, 9998.0 / 3.0, 5.0 * 47.0);
}

// Independent reference: split x into runs of equal values; a run is a maximum (minimum) when
// both neighbouring runs are lower (higher); zero crossings between consecutive non-zero samples.
Found Reference(const std::vector<double>& x) {
  Found f;
  std::vector<std::pair<int, int>> runs;  // [first, last] sample of each run of equal values.
  for (int i = 0; i < static_cast<int>(x.size()); ++i) {
    if (runs.empty() || x[i] != x[runs.back().first]) runs.push_back({i, i});
    runs.back().second = i;
  }
  for (size_t r = 1; r + 1 < runs.size(); ++r) {
    const double v = x[runs[r].first], before = x[runs[r - 1].first], after = x[runs[r + 1].first];
    if (v > before && v > after) f.max_pos2.push_back(runs[r].first + runs[r].second);
    if (v < before && v < after) f.min_pos2.push_back(runs[r].first + runs[r].second);
  }
  double last = 0.0;
  for (double v : x) {
    if (v == 0.0) continue;
    if (last != 0.0 && (v > 0) != (last > 0)) ++f.counts.num_zero_crossings;
    last = v;
  }
  f.counts.num_maxima = static_cast<int>(f.max_pos2.size());
  f.counts.num_minima = static_cast<int>(f.min_pos2.size());
  return f;
}

TEST(Extrema, AgreesWithARunBasedReferenceOnNoiseWithFlatRunsAndZeros) {
  // Coarsely quantized noise has flat runs and exact zeros scattered through it; the fast path
  // (64-sample blocks without either) and the scalar path must hand over state exactly.
  for (double step : {0.0, 0.25, 1.0}) {
    const Eigen::VectorXd w = testing::WhiteNoise(5000, 77);
    std::vector<double> x(w.size());
    for (int i = 0; i < w.size(); ++i) {
      x[i] = step > 0.0 ? step * std::round(w[i] / step) : w[i];
      // Long flat runs and zeros in a few places, some crossing 64-sample block edges.
      if (i % 700 >= 60 && i % 700 < 70) x[i] = 0.0;
      if (i % 900 >= 120 && i % 900 < 135) x[i] = 0.5;
    }
    EnvelopeKnots maxima, minima;
    const Found got = Find(x, &maxima, &minima);
    const Found want = Reference(x);
    EXPECT_EQ(got.max_pos2, want.max_pos2) << "quantization step " << step;
    EXPECT_EQ(got.min_pos2, want.min_pos2) << "quantization step " << step;
    EXPECT_EQ(got.counts.num_zero_crossings, want.counts.num_zero_crossings);
    EXPECT_EQ(got.counts.num_maxima, want.counts.num_maxima);
  }
}

// The scan in parts must give exactly the serial scan's counts and knots (the serial scan is held
// to the run-based reference above) for any split: signals with flat runs and zeros straddling
// the part boundaries (a boundary inside a plateau, at its first or last sample, inside a run of
// zeros, on a tie between two samples), constant and monotone signals, tiny signals, more parts
// than steps, knot sets too small, and the parts run in reverse order or on threads.
Found FindInParts(const std::vector<double>& x, int capacity, int parts, const ForEach& for_each,
                  ExtremaScratch* scratch) {
  EnvelopeKnots maxima, minima;
  maxima.Reserve(capacity);
  minima.Reserve(capacity);
  Found f;
  f.counts = FindExtremaInParts(x.data(), static_cast<int>(x.size()), &maxima, &minima, parts,
                                for_each, scratch);
  for (int k = 0; k < maxima.num_interior(); ++k) f.max_pos2.push_back(maxima.interior_pos2(k));
  for (int k = 0; k < minima.num_interior(); ++k) f.min_pos2.push_back(minima.interior_pos2(k));
  return f;
}

void ExpectSameScan(const Found& got, const Found& want, const std::string& what) {
  EXPECT_EQ(got.max_pos2, want.max_pos2) << what;
  EXPECT_EQ(got.min_pos2, want.min_pos2) << what;
  EXPECT_EQ(got.counts.num_maxima, want.counts.num_maxima) << what;
  EXPECT_EQ(got.counts.num_minima, want.counts.num_minima) << what;
  EXPECT_EQ(got.counts.num_zero_crossings, want.counts.num_zero_crossings) << what;
}

TEST(Extrema, ScanInPartsEqualsTheSerialScanForEverySplitAndSchedule) {
  const ForEach in_order = [](int n, const std::function<void(int)>& body) {
    for (int i = 0; i < n; ++i) body(i);
  };
  const ForEach reversed = [](int n, const std::function<void(int)>& body) {
    for (int i = n - 1; i >= 0; --i) body(i);
  };
  const ForEach threaded = [](int n, const std::function<void(int)>& body) {
    std::vector<std::thread> threads;
    for (int i = 0; i < n; ++i) threads.emplace_back([&body, i] { body(i); });
    for (std::thread& t : threads) t.join();
  };
  std::vector<std::pair<std::string, std::vector<double>>> signals;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const int n = 3000 + 517 * static_cast<int>(seed);
    const Eigen::VectorXd w = testing::WhiteNoise(n, seed);
    std::vector<double> plain(w.data(), w.data() + n), plateaus(n);
    for (int i = 0; i < n; ++i) {
      // Coarse quantization: ties between neighbours and exact zeros everywhere.
      plateaus[i] = (seed % 2 ? 0.5 : 1.0) * std::round(w[i] / (seed % 2 ? 0.5 : 1.0));
    }
    // Plateaus and zero runs of several lengths centred on the boundaries of 2..8 parts.
    std::vector<double> boundaries = plain;
    for (int parts = 2; parts <= 8; ++parts) {
      for (int p = 1; p < parts; ++p) {
        const int b = 1 + static_cast<int>(static_cast<int64_t>(n - 1) * p / parts);
        const int half = (parts + p + static_cast<int>(seed)) % 5;  // 0..4 samples either side
        const double level = (p % 3 == 0) ? 0.0 : (p % 3 == 1 ? 3.0 : -3.0);
        for (int i = std::max(0, b - half); i <= std::min(n - 1, b + half - (p % 2)); ++i)
          boundaries[i] = level;
      }
    }
    signals.push_back({"white noise " + std::to_string(seed), plain});
    signals.push_back({"quantized noise " + std::to_string(seed), plateaus});
    signals.push_back({"plateaus on part boundaries " + std::to_string(seed), boundaries});
  }
  signals.push_back({"constant", std::vector<double>(1000, 2.0)});
  signals.push_back({"zeros", std::vector<double>(1000, 0.0)});
  std::vector<double> ramp(1000);
  for (int i = 0; i < 1000; ++i) ramp[i] = i < 500 ? i : 1000 - i;  // one maximum, at 500
  signals.push_back({"tent", ramp});
  const std::vector<double> tiny = {1.0, -1.0, 2.0, 2.0, 0.0};
  for (int n = 0; n <= 5; ++n)
    signals.push_back({"tiny " + std::to_string(n), {tiny.begin(), tiny.begin() + n}});

  for (const auto& [name, x] : signals) {
    const int n = static_cast<int>(x.size());
    for (const int capacity : {std::max(n, 1), 7}) {
      EnvelopeKnots maxima, minima;
      maxima.Reserve(capacity);
      minima.Reserve(capacity);
      Found want;
      want.counts = FindExtrema(x.data(), n, &maxima, &minima);
      for (int k = 0; k < maxima.num_interior(); ++k)
        want.max_pos2.push_back(maxima.interior_pos2(k));
      for (int k = 0; k < minima.num_interior(); ++k)
        want.min_pos2.push_back(minima.interior_pos2(k));
      ExtremaScratch scratch;  // reused across splits, as the EMD reuses it across sifts
      // More parts than steps only where that stays a few threads.
      for (int parts : {2, 3, 5, 8, 16, 17, n < 50 ? n + 3 : 4}) {
        for (const ForEach* each : {&in_order, &reversed, &threaded}) {
          const std::string what = name + ", capacity " + std::to_string(capacity) + ", " +
                                   std::to_string(parts) + " parts";
          ExpectSameScan(FindInParts(x, capacity, parts, *each, &scratch), want, what);
        }
      }
      // Counting alone, in parts.
      const ExtremaCounts counted =
          FindExtremaInParts(x.data(), n, nullptr, nullptr, 5, threaded, nullptr);
      EXPECT_EQ(counted.num_maxima, want.counts.num_maxima) << name;
      EXPECT_EQ(counted.num_minima, want.counts.num_minima) << name;
      EXPECT_EQ(counted.num_zero_crossings, want.counts.num_zero_crossings) << name;
    }
  }
}

// Mirrored knots must extend both envelopes past both ends, keep positions strictly increasing,
// and be reflections (same values) of extrema or of the end samples.
void ExpectValidMirror(const std::vector<double>& x) {
  const int n = static_cast<int>(x.size());
  EnvelopeKnots maxima, minima;
  Find(x, &maxima, &minima);
  MirrorEnds(x.data(), n, &maxima, &minima);
  for (const EnvelopeKnots* k : {&maxima, &minima}) {
    ASSERT_GE(k->size(), k->num_interior() + 2);
    EXPECT_LE(k->pos2(0), 0);
    EXPECT_GE(k->pos2(k->size() - 1), 2 * (n - 1));
    for (int j = 1; j < k->size(); ++j) EXPECT_LT(k->pos2(j - 1), k->pos2(j));
  }
}

TEST(Extrema, MirrorEndsCoversBothEndsForEveryEndConfiguration) {
  // Sines with phases putting every kind of sample at the ends (first extremum max or min, end
  // sample beyond it or not), and white noise.
  for (int phase = 0; phase < 16; ++phase) {
    std::vector<double> x(97);
    for (int i = 0; i < 97; ++i) x[i] = std::sin(2.0 * M_PI * i / 23.0 + phase * M_PI / 8.0);
    ExpectValidMirror(x);
  }
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const Eigen::VectorXd w = testing::WhiteNoise(50, seed);
    ExpectValidMirror(std::vector<double>(w.data(), w.data() + w.size()));
  }
}

TEST(Extrema, MirrorEndsReflectsAboutTheFirstExtremumWhenTheEndLiesInside) {
  // First extremum: maximum at sample 2 (value 3); x[0] = 1 lies above the first minimum (-2 at
  // sample 4), so Rilling's rule reflects about that maximum: the maxima at samples 6 and 10 go
  // to -2 and -6 (pos2 -4, -12), the minima at 4 and 8 to 0 and -4 (pos2 0, -8).
  const std::vector<double> x = {1.0, 2.0, 3.0, 0.0, -2.0, 0.0, 2.5, 0.0, -1.5, 0.0, 2.0, 1.0};
  EnvelopeKnots maxima, minima;
  Find(x, &maxima, &minima);
  MirrorEnds(x.data(), static_cast<int>(x.size()), &maxima, &minima);
  EXPECT_EQ(maxima.pos2(0), -12);
  EXPECT_EQ(maxima.pos2(1), -4);
  EXPECT_DOUBLE_EQ(maxima.y(0), 2.0);  // Sample 10 reflected.
  EXPECT_DOUBLE_EQ(maxima.y(1), 2.5);  // Sample 6 reflected.
  EXPECT_EQ(minima.pos2(0), -8);
  EXPECT_EQ(minima.pos2(1), 0);
  EXPECT_DOUBLE_EQ(minima.y(0), -1.5);
  EXPECT_DOUBLE_EQ(minima.y(1), -2.0);
}

TEST(Extrema, MirrorEndsUsesTheEndSampleWhenItLiesBeyondTheFirstExtremum) {
  // x[0] = -5 is below the first minimum (-2 at sample 4) after a first maximum at sample 2: the
  // reflection is about sample 0, which becomes a minimum knot with its own value.
  const std::vector<double> x = {-5.0, 2.0, 3.0, 0.0, -2.0, 0.0, 2.5, 0.0, -1.5, 0.0, 2.0, 1.0};
  EnvelopeKnots maxima, minima;
  Find(x, &maxima, &minima);
  MirrorEnds(x.data(), static_cast<int>(x.size()), &maxima, &minima);
  EXPECT_EQ(maxima.pos2(0), -12);  // Samples 6 and 2 reflected about 0.
  EXPECT_EQ(maxima.pos2(1), -4);
  EXPECT_EQ(minima.pos2(0), -8);  // Sample 4 reflected, then the end sample itself.
  EXPECT_EQ(minima.pos2(1), 0);
  EXPECT_DOUBLE_EQ(minima.y(1), -5.0);
}

}  // namespace
}  // namespace fogpipe::emd
