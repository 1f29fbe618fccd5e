// Tests algorithms/common/eigen_sums.h against the Eigen calls it stands for, to the last bit.
#include "algorithms/common/eigen_sums.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace fogpipe {
namespace {

std::uint64_t Bits(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  return bits;
}

TEST(DotsWithEigensOrder, EachSumHasTheBitsOfItsEigenCallAtEveryLengthAndOffset) {
  // Values spread over many magnitudes, so that a different order of the additions rounds
  // differently; every length from 0 to past several pairs of AVX-512 packets, and start offsets
  // within a cache line (aligned and unaligned loads, the arrays offset from each other as Burg's
  // errors and a series' lags are). Burg's three sums (a dot product and two squared norms) and
  // five lags of one series.
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  std::vector<double> x(512), y(512);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = std::ldexp(mantissa(rng), exponent(rng));
    y[i] = std::ldexp(mantissa(rng), exponent(rng));
  }
  int compared = 0, differs_from_a_plain_loop = 0;
  for (Eigen::Index n = 0; n <= 100; ++n) {
    for (int offset_a = 0; offset_a < 8; ++offset_a) {
      for (int offset_b = 0; offset_b < 8; offset_b += 3) {
        const double* a = x.data() + offset_a;
        const double* b = y.data() + offset_b;
        const Eigen::Map<const Eigen::VectorXd> ma(a, n), mb(b, n);
        double burg[3];
        DotsWithEigensOrder<3>({a, a, b}, {b, a, b}, n, burg);
        ASSERT_EQ(Bits(burg[0]), Bits(ma.dot(mb))) << n << " " << offset_a << " " << offset_b;
        ASSERT_EQ(Bits(burg[1]), Bits(ma.squaredNorm())) << n << " " << offset_a;
        ASSERT_EQ(Bits(burg[2]), Bits(mb.squaredNorm())) << n << " " << offset_b;
        double lags[5];
        DotsWithEigensOrder<5>({a, a, a, a, a}, {a, a + 1, a + 2, a + 3, a + 4}, n, lags);
        for (int k = 0; k < 5; ++k) {
          const Eigen::Map<const Eigen::VectorXd> lagged(a + k, n);
          ASSERT_EQ(Bits(lags[k]), Bits(ma.dot(lagged))) << n << " " << offset_a << " lag " << k;
        }
        double plain = 0.0;
        for (Eigen::Index i = 0; i < n; ++i) plain += a[i] * b[i];
        differs_from_a_plain_loop += Bits(plain) != Bits(burg[0]);
        ++compared;
      }
    }
  }
  // The order matters on these values: a sum in plain order misses Eigen's bits on many of them,
  // so the equalities above are not met by any order.
  EXPECT_GT(differs_from_a_plain_loop, compared / 4) << "of " << compared;
}

}  // namespace
}  // namespace fogpipe
