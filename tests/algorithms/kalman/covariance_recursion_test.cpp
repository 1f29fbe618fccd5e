#include "algorithms/kalman/covariance_recursion.h"

#include <gtest/gtest.h>

#include <cstring>

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

}  // namespace
}  // namespace fogpipe::kalman::internal
