// Coverage of ComputeAllan's confidence intervals (algorithms/allan/allan.{h,cpp} with
// noise_id.h and edf.h): over many realisations of power-law noise whose Allan variance is known
// exactly (power_law_noise.h), the fraction of intervals that contain the true deviation, at every
// tau of the octave grid.
//
// The study behind docs/allan-statistics.md runs the same code on more and longer records:
//   FOGPIPE_ALLAN_COVERAGE_STUDY=<realisations>,<log2 samples>,<first seed>
//     build/tests/algorithms/allan/allan_coverage_test --gtest_filter='*Study*'
// prints one table per noise and noise-identification rule. Its seeds start at 1000001; this CI
// test uses seeds from 1 (design and test seeds are separate).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/edf.h"
#include "algorithms/allan/model_edf.h"
#include "algorithms/allan/noise_fit.h"
#include "tests/algorithms/allan/power_law_noise.h"

namespace fogpipe::allan {
namespace {

using testing::PowerLawNoise;
using testing::PowerLawTerm;

struct NoiseCase {
  std::string name;
  std::vector<PowerLawTerm> terms;
};

// The five pure power laws and a navigation-grade gyro mixture: white PM (quantization) dominant
// at m = 1, white FM (angle random walk) to m ~ n / 256, flicker FM (bias instability) to
// m ~ n / 16, random-walk FM beyond. Levels from the Allan variances of each law at low
// frequency: white PM 3 h / m^2, white FM h / m, flicker FM 2 ln 2 h / pi, random-walk FM h m / 3.
std::vector<NoiseCase> Cases(long long n) {
  const double m_flicker = static_cast<double>(n) / 256.0, m_walk = static_cast<double>(n) / 16.0;
  const double h_flicker = std::acos(-1.0) / (2.0 * std::log(2.0) * m_flicker);
  const double floor_avar = 1.0 / m_flicker;
  const double h_walk = 3.0 * floor_avar / m_walk;
  return {{"white PM", {{2, 1.0}}},
          {"flicker PM", {{1, 1.0}}},
          {"white FM", {{0, 1.0}}},
          {"flicker FM", {{-1, 1.0}}},
          {"random-walk FM", {{-2, 1.0}}},
          {"navigation gyro", {{2, 0.5}, {0, 1.0}, {-1, h_flicker}, {-2, h_walk}}}};
}

struct CoverageRow {
  long long m = 0;
  int covered = 0, total = 0;
  int below = 0;  // intervals entirely below the truth
  double edf_sum = 0.0;
  int phase_noise = 0;                   // rows identified as phase noise (alpha >= 1)
  int alpha_count[5] = {0, 0, 0, 0, 0};  // identified alpha = 2 - index
  int covered_true_alpha[2] = {0, 0};  // with the EDF of the dominant true alpha (printed, sampled)
  int model_edf = 0;                   // rows whose EDF came from the fitted model
  int identified_true = 0, covered_identified_true = 0;  // rows read as the true alpha (printed)
  int covered_true_law = 0;  // with the true alpha's law or EDF, as the calibrated rule makes them
};

// One way of making the intervals: the Allan options, then optionally the fitted model's EDF
// (model_edf.h) where the model describes the curve, as `fogpipe allan` and `run` do.
struct Variant {
  AllanOptions options;
  bool model_edf = true;
};

// The true variance behind each deviation kind (power_law_noise.h); TDEV's is tau^2 MVAR / 3
// with tau = m samples. NaN for TOTDEV, which estimates the Allan variance with a bias of its own.
double TrueVariance(const PowerLawNoise& noise, Deviation deviation, long long m) {
  switch (deviation) {
    case Deviation::kOverlappingAllan:
    case Deviation::kAllan:
      return noise.TrueAllanVariance(m);
    case Deviation::kOverlappingHadamard:
    case Deviation::kHadamard:
      return noise.TrueHadamardVariance(m);
    case Deviation::kModifiedAllan:
      return noise.TrueModifiedAllanVariance(m);
    case Deviation::kTime:
      return noise.TrueModifiedAllanVariance(m) * static_cast<double>(m * m) / 3.0;
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

// Coverage of each option set in `variants` on the same realisations.
std::vector<std::vector<CoverageRow>> Coverage(const NoiseCase& c, long long n, int realisations,
                                               std::uint64_t first_seed,
                                               const std::vector<Variant>& variants,
                                               int true_alpha = 99) {
  const PowerLawNoise noise(c.terms, n);
  std::vector<std::vector<CoverageRow>> out(variants.size());
  std::vector<std::vector<double>> truths(variants.size());
  for (int r = 0; r < realisations; ++r) {
    const Eigen::VectorXd rate = noise.Draw(first_seed + r);
    for (size_t v = 0; v < variants.size(); ++v) {
      const AllanOptions& options = variants[v].options;
      std::vector<CoverageRow>& rows = out[v];
      AllanTable t = ComputeAllan(rate, 1.0, options).table;
      if (variants[v].model_edf) {
        ModelEdfOptions model;
        model.confidence = options.confidence;
        ApplyModelEdf(FitNoiseTerms(t, NoiseFitOptions()), model, &t);
      }
      std::vector<double>& truth = truths[v];
      if (truth.empty())
        for (size_t k = 0; k < t.size(); ++k)
          truth.push_back(std::sqrt(TrueVariance(noise, options.deviation, t.m[k])));
      if (rows.empty()) {
        rows.resize(t.size());
        for (size_t k = 0; k < t.size(); ++k) rows[k].m = t.m[k];
      }
      for (size_t k = 0; k < rows.size(); ++k) {
        ++rows[k].total;
        rows[k].covered += t.ci_low[k] <= truth[k] && truth[k] <= t.ci_high[k];
        rows[k].below += t.ci_high[k] < truth[k];
        rows[k].edf_sum += t.edf[k];
        rows[k].phase_noise += t.alpha[k] >= 1;
        rows[k].model_edf += t.edf_source[k] == EdfSource::kModel;
        if (t.alpha[k] >= -2 && t.alpha[k] <= 2) ++rows[k].alpha_count[2 - t.alpha[k]];
        if (true_alpha == 99) continue;
        {
          // The interval the product's rule would make from the true type.
          const NoiseTypeInterval i =
              IntervalForNoiseType(options, true_alpha, t.m[k], t.count[k], n, t.sigma[k]);
          rows[k].covered_true_law += i.ci_low <= truth[k] && truth[k] <= i.ci_high;
        }
        if (t.alpha[k] == true_alpha) {
          ++rows[k].identified_true;
          rows[k].covered_identified_true += t.ci_low[k] <= truth[k] && truth[k] <= t.ci_high[k];
        }
        for (int sampled = 0; sampled < 2; ++sampled) {
          double low = 0.0, high = 0.0;
          ConfidenceBounds(t.sigma[k],
                           DeviationEdf(options.deviation, true_alpha, t.m[k], n, sampled == 1),
                           options.confidence, &low, &high);
          rows[k].covered_true_alpha[sampled] += low <= truth[k] && truth[k] <= high;
        }
      }
    }
  }
  return out;
}

std::vector<CoverageRow> Coverage(const NoiseCase& c, long long n, int realisations,
                                  std::uint64_t first_seed, const Variant& variant) {
  return Coverage(c, n, realisations, first_seed, std::vector<Variant>{variant})[0];
}

void Print(const NoiseCase& c, const char* rule, const std::vector<CoverageRow>& rows) {
  std::printf("| noise | rule | coverage at m =");
  for (const CoverageRow& row : rows) std::printf(" %lld", row.m);
  std::printf(" |\n| %s | %s |", c.name.c_str(), rule);
  for (const CoverageRow& row : rows)
    std::printf(" %.3f", static_cast<double>(row.covered) / row.total);
  std::printf(" |\n");
}

// The exact truth against closed forms: white FM h / m, white PM 3 h / m^2 (the second difference
// of white phase has variance 6 h).
TEST(PowerLawNoise, TrueAllanVarianceEqualsTheClosedFormsOfWhiteFmAndWhitePm) {
  const PowerLawNoise white_fm({{0, 2.0}}, 1024), white_pm({{2, 2.0}}, 1024);
  for (long long m : {1LL, 3LL, 64LL, 512LL}) {
    EXPECT_NEAR(white_fm.TrueAllanVariance(m), 2.0 / m, 1e-12 / m) << m;
    EXPECT_NEAR(white_pm.TrueAllanVariance(m), 6.0 / (m * m), 1e-12 / (m * m)) << m;
  }
}

// Closed forms of white FM and white PM for the other variances: white FM's Hadamard variance is
// h / m (weights 1, -2, 1 on three independent averages, over 6), white PM's 20 h / (6 m^2) (the
// third difference of white phase has variance (1 + 9 + 9 + 1) h).
TEST(PowerLawNoise, TrueHadamardVarianceEqualsTheClosedFormsOfWhiteFmAndWhitePm) {
  const PowerLawNoise white_fm({{0, 2.0}}, 1024), white_pm({{2, 2.0}}, 1024);
  for (long long m : {1LL, 3LL, 64LL, 256LL}) {
    EXPECT_NEAR(white_fm.TrueHadamardVariance(m), 2.0 / m, 1e-12 / m) << m;
    EXPECT_NEAR(white_pm.TrueHadamardVariance(m), 40.0 / (6.0 * m * m), 1e-12 / (m * m)) << m;
  }
}

// The simulator against its own truth, for the laws and kinds without a closed form: the mean of
// the overlapping Allan, overlapping Hadamard and modified Allan variances over 400 realisations
// equals the true one within 4 standard errors of that mean (each estimator is unbiased for a
// stationary process: every difference has the same variance).
TEST(PowerLawNoise, MeanVarianceOfRealisationsEqualsTheTruth) {
  const long long n = 4096;
  const std::vector<Deviation> kinds = {Deviation::kOverlappingAllan,
                                        Deviation::kOverlappingHadamard, Deviation::kModifiedAllan};
  for (int alpha : {2, 1, 0, -1, -2}) {
    const PowerLawNoise noise({{alpha, 1.0}}, n);
    const int realisations = 400;
    std::vector<std::vector<double>> sum(kinds.size()), sum_sq(kinds.size());
    std::vector<std::vector<long long>> m(kinds.size());
    for (int r = 0; r < realisations; ++r) {
      const Eigen::VectorXd rate = noise.Draw(500 + r);
      for (size_t d = 0; d < kinds.size(); ++d) {
        AllanOptions options;
        options.confidence_intervals = false;
        options.deviation = kinds[d];
        const AllanTable t = ComputeAllan(rate, 1.0, options).table;
        if (sum[d].empty())
          sum[d].assign(t.size(), 0.0), sum_sq[d].assign(t.size(), 0.0), m[d] = t.m;
        for (size_t k = 0; k < t.size(); ++k) {
          const double v = t.sigma[k] * t.sigma[k];
          sum[d][k] += v, sum_sq[d][k] += v * v;
        }
      }
    }
    for (size_t d = 0; d < kinds.size(); ++d) {
      for (size_t k = 0; k < m[d].size(); ++k) {
        if (n / m[d][k] < 8) continue;  // there the variance of the estimate is itself heavy-tailed
        const double mean = sum[d][k] / realisations;
        const double se =
            std::sqrt((sum_sq[d][k] / realisations - mean * mean) / (realisations - 1));
        EXPECT_NEAR(mean, TrueVariance(noise, kinds[d], m[d][k]), 4.0 * se)
            << ToString(kinds[d]) << " alpha " << alpha << " m " << m[d][k];
      }
    }
  }
}

// The acceptance band is 63-73 % for the nominal 68.3 % interval (docs/allan-statistics.md has
// the study at 2^18 samples and 1000 realisations). Here 400 realisations of 2^14 samples: the
// estimated coverage of one row has standard error sqrt(0.683 x 0.317 / 400) = 0.023. Over the
// 6 x 14 = 84 rows, a row whose true coverage sits exactly at a band edge is failed with family
// probability 1 % at z = Phi^-1(1 - 0.01 / 84) = 3.67 standard errors, so each row must lie in
// [0.63 - 0.085, 0.73 + 0.085]. Rows are also printed so that a drift shows before it fails.
TEST(AllanCoverage, SixtyEightPercentIntervalsCoverTheTrueDeviationAtEveryOctaveTau) {
  const long long n = 1 << 14;
  const int realisations = 400;
  const double se = std::sqrt(0.683 * 0.317 / realisations);
  const double z = 3.67;
  AllanOptions options;
  for (const NoiseCase& c : Cases(n)) {
    const std::vector<CoverageRow> rows = Coverage(c, n, realisations, 1, Variant{options});
    ASSERT_EQ(rows.size(), 14u) << c.name;
    Print(c, "calibrated", rows);
    for (const CoverageRow& row : rows) {
      const double coverage = static_cast<double>(row.covered) / row.total;
      EXPECT_GE(coverage, 0.63 - z * se) << c.name << " m=" << row.m;
      EXPECT_LE(coverage, 0.73 + z * se) << c.name << " m=" << row.m;
    }
  }
}

// The failure this rule was built against: pure white FM misread as phase noise, whose EDF is up
// to ten times larger, at the long taus where only tens of averages exist. Over 400 records of
// 2^14 samples, rows with 8..1000 averages: the fraction identified as phase noise is at most
// 1 % (the lag-1 method alone misreads 4-10 % at 40-90 averages).
TEST(AllanCoverage, WhiteFmIsAlmostNeverReadAsPhaseNoiseAtLongTau) {
  const long long n = 1 << 14;
  const int realisations = 400;
  const NoiseCase white{"white FM", {{0, 1.0}}};
  const std::vector<CoverageRow> rows =
      Coverage(white, n, realisations, 1, Variant{AllanOptions(), false});
  int phase = 0, total = 0;
  for (const CoverageRow& row : rows) {
    if (n / row.m < 8 || n / row.m > 1000) continue;
    phase += row.phase_noise, total += row.total;
  }
  std::printf("white FM read as phase noise: %d of %d rows\n", phase, total);
  EXPECT_LE(phase, total / 100);
}

// The study (see the header); skipped unless FOGPIPE_ALLAN_COVERAGE_STUDY is set.
TEST(AllanCoverage, Study) {
  const char* spec = std::getenv("FOGPIPE_ALLAN_COVERAGE_STUDY");
  if (spec == nullptr) GTEST_SKIP() << "set FOGPIPE_ALLAN_COVERAGE_STUDY=<reps>,<log2 n>,<seed>";
  int realisations = 0, log2n = 0;
  unsigned long long seed = 0;
  ASSERT_EQ(std::sscanf(spec, "%d,%d,%llu", &realisations, &log2n, &seed), 3);
  const long long n = 1LL << log2n;
  const char* only = std::getenv("FOGPIPE_ALLAN_COVERAGE_NOISE");
  for (const NoiseCase& c : Cases(n)) {
    if (only != nullptr && c.name != only) continue;
    std::vector<Variant> variants;
    std::vector<std::string> labels;
    for (NoiseIdRule rule : {NoiseIdRule::kCalibrated, NoiseIdRule::kStable32}) {
      for (bool sampled : {false, true}) {
        for (bool model : {false, true}) {
          if (model && !(rule == NoiseIdRule::kCalibrated && sampled)) continue;
          Variant v;
          v.options.noise_id = rule;
          v.options.sampled_phase_edf = sampled;
          v.model_edf = model;
          variants.push_back(v);
          labels.push_back(std::string(ToString(rule)) +
                           (sampled ? ", sampled-phase EDF" : ", printed EDF") +
                           (model ? ", model EDF where the fit holds" : ""));
        }
      }
    }
    // The other kinds with their defaults (calibrated rule, sampled-phase EDF; no model EDF, which
    // is OADEV's).
    for (Deviation d : {Deviation::kAllan, Deviation::kOverlappingHadamard, Deviation::kHadamard,
                        Deviation::kModifiedAllan}) {
      Variant v;
      v.options.deviation = d;
      v.model_edf = false;
      variants.push_back(v);
      labels.push_back(std::string(ToString(d)) + ", calibrated, sampled-phase EDF");
    }
    // FOGPIPE_ALLAN_COVERAGE_KIND=<deviation> keeps only that kind's variants.
    if (const char* kind = std::getenv("FOGPIPE_ALLAN_COVERAGE_KIND")) {
      std::vector<Variant> kept;
      std::vector<std::string> kept_labels;
      for (size_t v = 0; v < variants.size(); ++v)
        if (std::string(ToString(variants[v].options.deviation)) == kind)
          kept.push_back(variants[v]), kept_labels.push_back(labels[v]);
      variants = kept, labels = kept_labels;
    }
    const auto all =
        Coverage(c, n, realisations, seed, variants, c.terms.size() == 1 ? c.terms[0].alpha : 99);
    for (size_t v = 0; v < variants.size(); ++v) {
      const std::vector<CoverageRow>& rows = all[v];
      Print(c, labels[v].c_str(), rows);
      std::printf("|   mean EDF |");
      for (const CoverageRow& row : rows) std::printf(" %.3g", row.edf_sum / row.total);
      std::printf(" |\n|   rows with the model EDF |");
      for (const CoverageRow& row : rows) std::printf(" %d", row.model_edf);
      std::printf(" |\n|   alpha 2/1/0/-1/-2 |");
      for (const CoverageRow& row : rows)
        std::printf(" %d/%d/%d/%d/%d", row.alpha_count[0], row.alpha_count[1], row.alpha_count[2],
                    row.alpha_count[3], row.alpha_count[4]);
      std::printf(" |\n");
      if (c.terms.size() == 1) {
        for (int sampled = 0; sampled < 2; ++sampled) {
          std::printf("|   true alpha, %s EDF |", sampled ? "sampled" : "printed");
          for (const CoverageRow& row : rows)
            std::printf(" %.3f", static_cast<double>(row.covered_true_alpha[sampled]) / row.total);
          std::printf(" |\n");
        }
        std::printf("|   true alpha, its law or own EDF |");
        for (const CoverageRow& row : rows)
          std::printf(" %.3f", static_cast<double>(row.covered_true_law) / row.total);
        std::printf(" |\n");
        std::printf("|   rows read as the true alpha: their coverage |");
        for (const CoverageRow& row : rows)
          std::printf(
              " %.3f (%d)",
              static_cast<double>(row.covered_identified_true) / std::max(1, row.identified_true),
              row.identified_true);
        std::printf(" |\n");
      }
      std::fflush(stdout);
    }
  }
}

}  // namespace
}  // namespace fogpipe::allan
