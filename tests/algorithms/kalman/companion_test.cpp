#include "algorithms/kalman/companion.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

namespace fogpipe::kalman {
namespace {

Eigen::MatrixXd RandomCovariance(int p, unsigned seed) {
  std::srand(seed);
  const Eigen::MatrixXd m = Eigen::MatrixXd::Random(p, p);
  return m * m.transpose() + Eigen::MatrixXd::Identity(p, p);
}

TEST(Companion, StructuredPredictionEqualsTheDenseProduct) {
  for (int p : {1, 2, 5, 20}) {
    const Eigen::VectorXd phi = Eigen::VectorXd::LinSpaced(p, 0.9, -0.3);
    const Eigen::MatrixXd pf = RandomCovariance(p, 7u + p);
    const Eigen::MatrixXd a = CompanionMatrix(phi);
    Eigen::MatrixXd dense = a * pf * a.transpose();
    dense(0, 0) += 0.25;
    Eigen::MatrixXd structured;
    PredictCovariance(pf, phi, 0.25, &structured);
    // Same sums in a different order: a few ulps of the largest entry.
    EXPECT_LE((structured - dense).cwiseAbs().maxCoeff(), 1e-13 * dense.cwiseAbs().maxCoeff());
  }
}

TEST(Companion, JosephUpdateEqualsTheDenseJosephAndTheShortForm) {
  for (int p : {1, 3, 8}) {
    const Eigen::MatrixXd pp = RandomCovariance(p, 11u + p);
    const double r = 0.3;
    Eigen::VectorXd g;
    Eigen::MatrixXd pf;
    const double s = JosephUpdate(pp, r, &g, &pf);
    EXPECT_DOUBLE_EQ(s, pp(0, 0) + r);
    Eigen::RowVectorXd h = Eigen::RowVectorXd::Zero(p);
    h[0] = 1.0;
    const Eigen::VectorXd g_ref = pp * h.transpose() / s;
    const Eigen::MatrixXd i_gh = Eigen::MatrixXd::Identity(p, p) - g_ref * h;
    const Eigen::MatrixXd joseph = i_gh * pp * i_gh.transpose() + r * g_ref * g_ref.transpose();
    const Eigen::MatrixXd short_form = i_gh * pp;
    EXPECT_LE((g - g_ref).norm(), 1e-15 * g_ref.norm());
    EXPECT_LE((pf - joseph).norm(), 1e-13 * pp.norm());
    EXPECT_LE((pf - short_form).norm(), 1e-13 * pp.norm());
    EXPECT_EQ((pf - pf.transpose()).norm(), 0.0);  // symmetric by construction
  }
}

}  // namespace
}  // namespace fogpipe::kalman
