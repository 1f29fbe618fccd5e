#include "algorithms/ar/stationarity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "algorithms/ar/ar_model.h"
#include "algorithms/ar/reflection.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::ar {
namespace {

// phi of prod_i (z - r_i) = z^p - phi_1 z^{p-1} - ... - phi_p. With dyadic roots of few bits
// every coefficient is exact in double, so the roots of the stored phi are exactly r_i: an
// independent closed form for the stored polynomial.
Eigen::VectorXd PhiFromRoots(const std::vector<double>& roots) {
  std::vector<double> c = {1.0};  // c_0 z^k + c_1 z^{k-1} + ...
  for (double r : roots) {
    std::vector<double> next(c.size() + 1, 0.0);
    for (std::size_t j = 0; j < c.size(); ++j) {
      next[j] += c[j];
      next[j + 1] -= r * c[j];
    }
    c = next;
  }
  Eigen::VectorXd phi(static_cast<Eigen::Index>(roots.size()));
  for (std::size_t i = 1; i < c.size(); ++i) phi(static_cast<Eigen::Index>(i) - 1) = -c[i];
  return phi;
}

// Roots 1 - 2^-8 (four times) and 1 +- 2^-14: the coefficients need at most 32 + 15 bits.
TEST(Stationarity, DecidesExactRootsBesideAClusterAndReportsTheirModulus) {
  const double cluster = 1.0 - std::ldexp(1.0, -8);
  for (double sign : {+1.0, -1.0}) {
    const double single = 1.0 + sign * std::ldexp(1.0, -14);
    const Eigen::VectorXd phi = PhiFromRoots({cluster, cluster, cluster, cluster, single});
    EXPECT_EQ(IsStationaryAsStored(phi), sign < 0.0) << "single root " << single;
    EXPECT_NEAR(MaxRootModulusAsStored(phi), single, 1e-14);
    const ArModel model = MakeArModel(phi, 1.0, 0.0, 1000);
    EXPECT_EQ(model.stationary, sign < 0.0);
    EXPECT_NEAR(model.max_root_modulus, single, 1e-14);
  }
}

// z^2 - phi_1 z - phi_2 with a complex pair has |z|^2 = -phi_2 exactly: one unit in the last place
// of phi_2 either side of -1 puts the pair either side of the unit circle, a difference of 1e-16
// in modulus that double-precision eigenvalues (relative error ~1e-16) cannot resolve.
TEST(Stationarity, ResolvesAComplexPairOneUlpFromTheUnitCircle) {
  Eigen::VectorXd phi(2);
  phi(0) = 2.0 * std::cos(0.01);
  phi(1) = -std::nextafter(1.0, 2.0);  // |z|^2 = 1 + 2^-52
  EXPECT_FALSE(IsStationaryAsStored(phi));
  EXPECT_GE(MaxRootModulusAsStored(phi), 1.0);
  phi(1) = -std::nextafter(1.0, 0.0);  // |z|^2 = 1 - 2^-53
  EXPECT_TRUE(IsStationaryAsStored(phi));
  EXPECT_LT(MaxRootModulusAsStored(phi), 1.0);
  EXPECT_NEAR(MaxRootModulusAsStored(phi), std::sqrt(-phi(1)), 1e-15);
}

// A Burg AR(4) of a trend (the residue of a real MEMS record) whose rounded coefficients sum to
// exactly 1: P(1) = 1 - sum phi_i = 0, a root exactly at z = 1 (the sum is exact in long double:
// the four exponents span two binary orders). A step-down in any finite precision rounds such a
// boundary case to either side; it must be called not stationary.
TEST(Stationarity, CallsARootExactlyAtOneNotStationary) {
  Eigen::VectorXd phi(4);
  phi << 2.2504046987130533, -0.7512141201925129, -1.2487858558546108, 0.7495952773340704;
  long double sum = 0.0L;
  for (int i = 0; i < 4; ++i) sum += static_cast<long double>(phi(i));
  ASSERT_EQ(sum, 1.0L);
  EXPECT_FALSE(IsStationaryAsStored(phi));
  EXPECT_GE(MaxRootModulusAsStored(phi), 1.0);
  EXPECT_FALSE(MakeArModel(phi, 1.0, 0.0, 1000).stationary);
}

// Away from the unit circle the double-precision eigenvalues are accurate, and both functions
// must agree with them and with each other: models from random reflection coefficients (Schur-Cohn:
// |kappa| < 1 gives a stationary model in exact arithmetic) and scaled ones.
TEST(Stationarity, AgreesWithCompanionEigenvaluesAwayFromTheUnitCircle) {
  simulation::RandomSource random(20261124);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int p = 1 + trial % 12;
    Eigen::VectorXd kappa(p);
    for (int m = 0; m < p; ++m) kappa(m) = std::tanh(random.Normal());
    Eigen::VectorXd phi = StepUp(kappa);
    // Scaling phi_i by s^i scales every root by s: half of the models become explosive.
    const double s = trial % 2 == 0 ? 1.0 : 1.05;
    for (int i = 0; i < p; ++i) phi(i) *= std::pow(s, i + 1);
    const double eigen = CharacteristicRoots(phi).cwiseAbs().maxCoeff();
    if (std::abs(eigen - 1.0) < 1e-6) continue;
    ++checked;
    EXPECT_EQ(IsStationaryAsStored(phi), eigen < 1.0) << "trial " << trial;
    EXPECT_NEAR(MaxRootModulusAsStored(phi), eigen, 1e-9 * std::max(1.0, eigen)) << trial;
  }
  EXPECT_GT(checked, 350);
}

// The case that matters: a cluster of roots near z = 1 (a slow component), coefficients rounded
// to double. (z - r)^k with r = 1 - 2^-12 expanded in double moves the cluster by about
// (1e-16)^(1/k) (Wilkinson): inside the circle for small k, across it for large k. Each verdict
// is checked against the stored model's own dynamics, independent of any root finding: the free
// response of an explosive model grows without bound, one with a root on the circle keeps its size
// (rounding can land a root there), and that of a stationary one dies out after its transient
// (which peaks near t = (k - 1) / (1 - r) = 3e4 steps). It runs in long double, so that
// the recursion's own rounding stays below the effect, for 4e6 steps.
TEST(Stationarity, AgreesWithTheFreeResponseOfRoundedRootClustersNearOne) {
  const double r = 1.0 - std::ldexp(1.0, -12);
  int explosive = 0, stationary = 0;
  for (int k = 2; k <= 9; ++k) {
    const Eigen::VectorXd phi = PhiFromRoots(std::vector<double>(static_cast<std::size_t>(k), r));
    const bool verdict = IsStationaryAsStored(phi);
    std::vector<long double> s(static_cast<std::size_t>(k), 0.0L);
    s[0] = 1.0L;
    long double peak_early = 0.0L, peak_late = 0.0L;
    const long steps = 4000000;
    bool overflow = false;
    for (long t = 0; t < steps && !overflow; ++t) {
      long double v = 0.0L;
      for (int i = 0; i < k; ++i) v += static_cast<long double>(phi(i)) * s[i];
      for (int i = k - 1; i > 0; --i) s[i] = s[i - 1];
      s[0] = v;
      const long double a = v < 0 ? -v : v;
      overflow = !(a < 1e300L);
      long double& peak = t < steps / 2 ? peak_early : peak_late;
      peak = std::max(peak, a);
    }
    // A stationary model's response has died out by the second half ((1 - 2^-12)^2e6 = e^-488
    // times its peak, whatever the cluster's polynomial factor); one with a root on or outside the
    // circle keeps or grows its size.
    const bool decays = !overflow && peak_late < 1e-6L * peak_early;
    EXPECT_EQ(verdict, decays) << "k = " << k << ": peaks " << static_cast<double>(peak_early)
                               << " then " << static_cast<double>(peak_late) << ", modulus "
                               << MaxRootModulusAsStored(phi);
    EXPECT_EQ(MaxRootModulusAsStored(phi) < 1.0, verdict) << "k = " << k;
    (verdict ? stationary : explosive) += 1;
  }
  // Both outcomes must occur, or the test does not test the boundary.
  EXPECT_GT(explosive, 0);
  EXPECT_GT(stationary, 0);
  std::printf("(z - (1 - 2^-12))^k rounded, k = 2..9: %d explosive, %d stationary\n", explosive,
              stationary);
}

}  // namespace
}  // namespace fogpipe::ar
