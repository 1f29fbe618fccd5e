#include "algorithms/kalman/covariance_recursion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "algorithms/common/fixed_order.h"
#include "algorithms/kalman/companion.h"

namespace fogpipe::kalman::internal {
namespace {

// The fused fixed-order step must be a faster way of computing exactly what PredictCovariance
// followed by JosephUpdate compute: the filter's output (FilterAr, ArFilterBank) must not depend on
// which of the two ran, so the comparison is to the last bit, over many steps (rounding differences
// would compound), on a stable and a near-unit-root model, from a diffuse and from a random start.
void ExpectSameBitsAsTheGenericSteps(int p, const Eigen::VectorXd& phi, const Eigen::MatrixXd& pf0,
                                     double q, double r) {
  Eigen::MatrixXd pf = pf0, pp;
  Eigen::VectorXd g;
  fixed_order::WithWideFixedOrder(p, [&](auto order) {
    constexpr int kP = decltype(order)::value;
    CovarianceRecursion<kP> recursion(pf0, phi, q, r);
    for (int k = 0; k < 300; ++k) {
      PredictCovariance(pf, phi, q, &pp);
      const double s_generic = JosephUpdate(pp, r, &g, &pf);
      const double s_fused = recursion.Step();
      ASSERT_EQ(std::memcmp(&s_fused, &s_generic, sizeof(double)), 0) << "p " << p << " step " << k;
      ASSERT_EQ(std::memcmp(recursion.gain(), g.data(), p * sizeof(double)), 0)
          << "p " << p << " step " << k;
    }
  });
}

TEST(CovarianceRecursion, GivesTheSameBitsAsPredictCovarianceThenJosephUpdateForEveryOrder) {
  for (int p = 1; p <= fixed_order::kMaxWideFixedOrder + 2; ++p) {
    // A stable model (geometrically falling coefficients) and a near-unit-root one (the slow
    // IMFs' kind: sum of coefficients 0.9999), each from a diffuse start (the paper's eq. 7) and
    // from a random positive-definite one.
    Eigen::VectorXd stable(p), slow(p);
    for (int i = 0; i < p; ++i) stable[i] = 0.5 * std::pow(-0.6, i);
    slow.setConstant(0.9999 / p);
    std::srand(17u + p);
    const Eigen::MatrixXd m = Eigen::MatrixXd::Random(p, p);
    const Eigen::MatrixXd random_start = m * m.transpose() + 0.1 * Eigen::MatrixXd::Identity(p, p);
    const Eigen::MatrixXd diffuse = 3.7 * Eigen::MatrixXd::Identity(p, p);
    for (const Eigen::VectorXd* phi : {&stable, &slow}) {
      ExpectSameBitsAsTheGenericSteps(p, *phi, diffuse, 0.013, 0.21);
      ExpectSameBitsAsTheGenericSteps(p, *phi, random_start, 1e-7, 2.5);
    }
  }
}

// Four recursions side by side (a bank's time-varying phases, ar_kalman.cpp) must give each lane
// the bits of its own scalar recursion: the replayed gains then filter exactly as FilterAr does.
// Every fixed order, lanes with different starts, q and r, and fewer than four active lanes.
TEST(CovarianceLanes, EachLaneGivesTheBitsOfItsOwnScalarRecursion) {
  for (int p = 1; p <= fixed_order::kMaxWideFixedOrder; ++p) {
    Eigen::VectorXd phi(p);
    for (int i = 0; i < p; ++i) phi[i] = 0.5 * std::pow(-0.6, i);
    if (p % 2 == 0) phi.setConstant(0.9999 / p);  // the slow IMFs' near-unit-root kind
    std::srand(29u + p);
    Eigen::MatrixXd starts[4];
    const Eigen::MatrixXd* start_pointers[4];
    for (int m = 0; m < 4; ++m) {
      const Eigen::MatrixXd a = Eigen::MatrixXd::Random(p, p);
      starts[m] = m == 0
                      ? Eigen::MatrixXd(3.7 * Eigen::MatrixXd::Identity(p, p))
                      : Eigen::MatrixXd(a * a.transpose() + 0.1 * Eigen::MatrixXd::Identity(p, p));
      start_pointers[m] = &starts[m];
    }
    const double q[4] = {0.013, 1e-7, 2.0, 1e-3};
    const double r[4] = {0.21, 2.5, 0.01, 1e3};
    for (int active = 1; active <= 4; ++active) {
      fixed_order::WithWideFixedOrder(p, [&](auto order) {
        constexpr int kP = decltype(order)::value;
        if constexpr (kP > 0) {
          CovarianceLanes<kP> lanes(start_pointers, phi, q, r, active);
          std::vector<CovarianceRecursion<kP>> scalar;
          for (int m = 0; m < active; ++m) scalar.emplace_back(starts[m], phi, q[m], r[m]);
          for (int k = 0; k < 300; ++k) {
            const CovarianceLanes4 s_lanes = lanes.Step();
            for (int m = 0; m < active; ++m) {
              const double s_scalar = scalar[m].Step();
              const double s_lane = s_lanes[m];
              ASSERT_EQ(std::memcmp(&s_lane, &s_scalar, sizeof(double)), 0)
                  << "p " << p << " lane " << m << " step " << k;
              for (int i = 0; i < p; ++i) {
                const double g_lane = lanes.gain()[i][m];
                ASSERT_EQ(std::memcmp(&g_lane, scalar[m].gain() + i, sizeof(double)), 0)
                    << "p " << p << " lane " << m << " step " << k << " element " << i;
              }
            }
          }
        }
      });
    }
  }
}

}  // namespace
}  // namespace fogpipe::kalman::internal
