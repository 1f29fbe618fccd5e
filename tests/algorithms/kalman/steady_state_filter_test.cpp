#include "algorithms/kalman/steady_state_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "algorithms/kalman/riccati.h"
#include "tests/algorithms/kalman/simulate_ar.h"

namespace fogpipe::kalman {
namespace {

// Reference: the constant-gain filter exactly as eqs. 10-11 state it, X = A X + G (z - H A X),
// with Eigen dense matrices.
void PlainLoop(const Eigen::VectorXd& z, double mean, const Eigen::VectorXd& phi,
               const Eigen::VectorXd& g, Eigen::VectorXd x, Eigen::VectorXd* out,
               Eigen::VectorXd* innovations) {
  const Eigen::Index p = phi.size();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(p, p);
  a.row(0) = phi.transpose();
  a.bottomLeftCorner(p - 1, p - 1).setIdentity();
  out->resize(z.size());
  innovations->resize(z.size());
  for (Eigen::Index k = 0; k < z.size(); ++k) {
    const Eigen::VectorXd xp = a * x;
    const double e = z[k] - mean - xp[0];
    x = xp + g * e;
    (*out)[k] = x[0] + mean;
    (*innovations)[k] = e;
  }
}

// The partial-sum (transposed direct form) loop is an exact regrouping of the plain one; from any
// starting state it must give the same x(k|k) and e(k) up to rounding. Orders 1..8 use the
// fixed-size kernels, 9 and 20 the runtime-order one.
TEST(SteadyStateFilter, EqualsThePlainStateSpaceLoopFromAnyState) {
  for (int p : {1, 2, 3, 4, 5, 6, 7, 8, 9, 20}) {
    // A stable AR(p): coefficients decaying so that sum |phi| = 0.9.
    Eigen::VectorXd phi(p);
    for (int i = 0; i < p; ++i) phi[i] = (i % 2 ? -1.0 : 1.0) * std::pow(0.5, i + 1);
    phi *= 0.9 / phi.cwiseAbs().sum();
    const DareSolution dare = SolveDare(phi, 0.5, 1.0);
    ASSERT_EQ(dare.summary.termination, Termination::kSuccess);
    const testing::ArSimulation sim = testing::SimulateArPlusNoise(phi, 0.5, 1.0, 5000, 40 + p);
    const double mean = 3.0;
    const Eigen::VectorXd z = sim.z.array() + mean;
    const Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(p, 1.0, -2.0);
    Eigen::VectorXd ref, ref_e;
    PlainLoop(z, mean, phi, dare.gain, x0, &ref, &ref_e);
    Eigen::VectorXd out(z.size()), e(z.size());
    SteadyStateFilter(z.data(), z.size(), mean, phi, dare.gain, x0, out.data(), e.data());
    // Stable loop (closed-loop radius < 0.9): rounding differences do not grow; a few ulps of the
    // signal scale (|z| < ~10) per step stay below 1e-13.
    EXPECT_LE((out - ref).cwiseAbs().maxCoeff(), 1e-13) << "p = " << p;
    EXPECT_LE((e - ref_e).cwiseAbs().maxCoeff(), 1e-13) << "p = " << p;
    // Without innovations requested, the same estimates.
    Eigen::VectorXd out2(z.size());
    SteadyStateFilter(z.data(), z.size(), mean, phi, dare.gain, x0, out2.data(), nullptr);
    EXPECT_EQ((out2 - out).cwiseAbs().maxCoeff(), 0.0);
  }
}

// The side-by-side loop continues each filter from its own state (as the sweep does after each
// filter's time-varying phase) with the single loop's arithmetic in the same order: the sums
// equal the single loop's estimates to the last bit, and so do the states left behind, whether the
// run is one call or split into pieces. Orders 1..13 (the fixed-order lane kernels up to 12, the
// runtime-order one) and 33 (one lane at a time); 1..6 filters (groups of four with idle lanes).
TEST(AddSteadyStateFilters, EachLaneEqualsTheSingleLoopFromItsOwnStateToTheLastBit) {
  for (int p : {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 33}) {
    Eigen::VectorXd phi(p);
    for (int i = 0; i < p; ++i) phi[i] = (i % 2 ? -1.0 : 1.0) * std::pow(0.5, i + 1);
    phi *= 0.9 / phi.cwiseAbs().sum();
    const testing::ArSimulation sim = testing::SimulateArPlusNoise(phi, 0.5, 1.0, 3000, 70 + p);
    for (int filters = 1; filters <= 6; ++filters) {
      std::vector<DareSolution> dares;
      std::vector<std::vector<double>> partial(filters), reference_partial(filters);
      std::vector<Eigen::VectorXd> sums(filters, Eigen::VectorXd::Zero(sim.z.size()));
      std::vector<Eigen::VectorXd> reference(filters, Eigen::VectorXd::Zero(sim.z.size()));
      std::vector<SteadyStateLane> lanes;
      for (int i = 0; i < filters; ++i) dares.push_back(SolveDare(phi, 0.1 * (i + 1), 1.0));
      for (int i = 0; i < filters; ++i) {
        const Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(p, 1.0 + i, -2.0);
        partial[i].resize(p);
        PartialPredictions(phi, x0, partial[i].data());
        reference_partial[i] = partial[i];
        SteadyStateFilterFromPartial(sim.z.data(), sim.z.size(), 0.1 * i, phi, dares[i].gain,
                                     reference_partial[i].data(), reference[i].data(), nullptr);
      }
      // In two pieces: the states carry over.
      for (long long begin : {0LL, 1234LL}) {
        const long long end = begin == 0 ? 1234 : sim.z.size();
        lanes.clear();
        for (int i = 0; i < filters; ++i) {
          lanes.push_back({&dares[i].gain, 0.1 * i, sums[i].data() + begin, partial[i].data()});
        }
        AddSteadyStateFilters(sim.z.data() + begin, end - begin, phi, lanes);
      }
      for (int i = 0; i < filters; ++i) {
        EXPECT_EQ((sums[i] - reference[i]).cwiseAbs().maxCoeff(), 0.0)
            << "p = " << p << ", filter " << i << " of " << filters;
        EXPECT_EQ(partial[i], reference_partial[i]) << "p = " << p << ", filter " << i;
      }
    }
  }
}

// Sums interleaved sample by sample (lane i's sample k at k * filters + i, as the sweep keeps
// them) let several groups of four lanes share one loop (two or three by order, measured in
// kalman_benchmark): every lane still equals the single loop to the last bit, with full and partial
// groups (4..13 filters), at the fixed orders and the runtime-order kernel, in two pieces.
TEST(AddSteadyStateFilters, InterleavedLanesInSeveralGroupsEqualTheSingleLoopToTheLastBit) {
  for (int p : {1, 2, 3, 5, 6, 7, 8, 11, 12, 13}) {
    Eigen::VectorXd phi(p);
    for (int i = 0; i < p; ++i) phi[i] = (i % 2 ? -1.0 : 1.0) * std::pow(0.5, i + 1);
    phi *= 0.9 / phi.cwiseAbs().sum();
    const testing::ArSimulation sim = testing::SimulateArPlusNoise(phi, 0.5, 1.0, 3000, 90 + p);
    const long long n = sim.z.size();
    for (int filters : {4, 5, 8, 9, 10, 12, 13}) {
      std::vector<DareSolution> dares;
      std::vector<std::vector<double>> partial(filters), reference_partial(filters);
      Eigen::VectorXd sums = Eigen::VectorXd::Constant(n * filters, 0.25);
      std::vector<Eigen::VectorXd> reference(filters, Eigen::VectorXd::Zero(n));
      for (int i = 0; i < filters; ++i) dares.push_back(SolveDare(phi, 0.05 * (i + 1), 1.0));
      for (int i = 0; i < filters; ++i) {
        const Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(p, 1.0 - i, 2.0);
        partial[i].resize(p);
        PartialPredictions(phi, x0, partial[i].data());
        reference_partial[i] = partial[i];
        SteadyStateFilterFromPartial(sim.z.data(), n, 0.1 * i, phi, dares[i].gain,
                                     reference_partial[i].data(), reference[i].data(), nullptr);
      }
      for (long long begin : {0LL, 1234LL}) {
        const long long end = begin == 0 ? 1234 : n;
        std::vector<SteadyStateLane> lanes;
        for (int i = 0; i < filters; ++i) {
          lanes.push_back({&dares[i].gain, 0.1 * i, sums.data() + begin * filters + i,
                           partial[i].data(), nullptr, filters});
        }
        AddSteadyStateFilters(sim.z.data() + begin, end - begin, phi, lanes);
      }
      for (int i = 0; i < filters; ++i) {
        // Each sum started at 0.25 and received one addition per sample.
        const Eigen::VectorXd expected = Eigen::VectorXd::Constant(n, 0.25) + reference[i];
        const Eigen::VectorXd got = Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>>(
            sums.data() + i, n, Eigen::InnerStride<>(filters));
        EXPECT_EQ((got - expected).cwiseAbs().maxCoeff(), 0.0)
            << "p = " << p << ", filter " << i << " of " << filters;
        EXPECT_EQ(partial[i], reference_partial[i]) << "p = " << p << ", filter " << i;
      }
    }
  }
}

}  // namespace
}  // namespace fogpipe::kalman
