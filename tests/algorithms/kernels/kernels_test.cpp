#include "algorithms/kernels/kernels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

namespace fogpipe::kernels {
namespace {

// Every kernel's four-lane variant against its scalar reference, lane by lane, to the last bit,
// on random inputs (seeded, so a failure repeats). The default build runs it natively, and
// scripts/test_portable_kernels.sh on the portable build (no FMA, two SSE registers per Lanes4).

constexpr int kLanes = 4;

std::uint64_t Bits(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  return bits;
}

// Uniform on [lo, hi).
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : engine_(seed) {}
  double operator()(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }

 private:
  std::mt19937_64 engine_;
};

// The four lanes' values as one vector.
Lanes4 Gather(const double (&v)[kLanes]) { return Lanes4{v[0], v[1], v[2], v[3]}; }

template <int P>
void ExpectCovarianceLanesEqualScalar(Draw& draw) {
  CovarianceStep<P, Lanes4> lanes;
  CovarianceStep<P, double> scalar[kLanes];
  for (int m = 0; m < kLanes; ++m) {
    CovarianceStep<P, double>& s = scalar[m];
    s.q = draw(0.01, 1.0);
    s.r = draw(0.01, 1.0);
    for (int i = 0; i < P; ++i) s.phi[i] = draw(-1.0, 1.0) / P;
    // P(0|0) = B B' + I, symmetric positive definite.
    double b[P * P];
    for (double& v : b) v = draw(-1.0, 1.0);
    for (int j = 0; j < P; ++j) {
      for (int i = 0; i < P; ++i) {
        double sum = i == j ? 1.0 : 0.0;
        for (int k = 0; k < P; ++k) sum += b[i * P + k] * b[j * P + k];
        s.pf[j * P + i] = sum;
      }
    }
    lanes.q[m] = s.q;
    lanes.r[m] = s.r;
    for (int i = 0; i < P * P; ++i) lanes.pf[i][m] = s.pf[i];
  }
  // One AR model per bank (the lanes share phi).
  for (int i = 0; i < P; ++i) {
    for (int m = 1; m < kLanes; ++m) scalar[m].phi[i] = scalar[0].phi[i];
    lanes.phi[i] = Splat<Lanes4>(scalar[0].phi[i]);
  }
  for (int step = 0; step < 64; ++step) {
    const Lanes4 s_lanes = lanes.Step();
    for (int m = 0; m < kLanes; ++m) {
      const double s = scalar[m].Step();
      ASSERT_EQ(Bits(s_lanes[m]), Bits(s)) << "P = " << P << " step " << step << " lane " << m;
      for (int i = 0; i < P; ++i)
        ASSERT_EQ(Bits(lanes.g[i][m]), Bits(scalar[m].g[i])) << "P = " << P << " gain " << i;
      for (int i = 0; i < P * P; ++i)
        ASSERT_EQ(Bits(lanes.pf[i][m]), Bits(scalar[m].pf[i])) << "P = " << P << " pf " << i;
    }
  }
}

template <int... P>
void ExpectCovarianceLanesEqualScalarAtOrders(std::integer_sequence<int, P...>, Draw& draw) {
  (ExpectCovarianceLanesEqualScalar<P + 1>(draw), ...);
}

TEST(Kernels, EachLaneOfTheCovarianceStepHasTheScalarStepsBits) {
  Draw draw(11);
  ExpectCovarianceLanesEqualScalarAtOrders(std::make_integer_sequence<int, 12>(), draw);
}

TEST(Kernels, EachLaneOfTheSteadyStateSampleHasTheScalarSamplesBits) {
  Draw draw(12);
  for (int p = 1; p <= 16; ++p) {
    std::vector<double> z(2000);
    for (double& v : z) v = draw(-3.0, 3.0);
    std::vector<double> phi(p), beta[kLanes], s[kLanes];
    double mean[kLanes], g0[kLanes];
    for (double& v : phi) v = draw(-1.0, 1.0) / p;
    for (int m = 0; m < kLanes; ++m) {
      mean[m] = draw(-1.0, 1.0);
      g0[m] = draw(0.0, 1.0);
      for (int i = 0; i < p; ++i) {
        beta[m].push_back(draw(-0.5, 0.5) / p);
        s[m].push_back(draw(-1.0, 1.0));
      }
    }
    std::vector<Lanes4> phi_v(p), beta_v(p), s_v(p);
    for (int i = 0; i < p; ++i) {
      phi_v[i] = Splat<Lanes4>(phi[i]);
      beta_v[i] = Lanes4{beta[0][i], beta[1][i], beta[2][i], beta[3][i]};
      s_v[i] = Lanes4{s[0][i], s[1][i], s[2][i], s[3][i]};
    }
    for (std::size_t k = 0; k < z.size(); ++k) {
      Lanes4 e_v;
      const Lanes4 deviation_v = SteadyStateSample(z[k], Gather(mean), Gather(g0), phi_v.data(),
                                                   beta_v.data(), p, s_v.data(), &e_v);
      for (int m = 0; m < kLanes; ++m) {
        double e;
        const double deviation =
            SteadyStateSample(z[k], mean[m], g0[m], phi.data(), beta[m].data(), p, s[m].data(), &e);
        ASSERT_EQ(Bits(deviation_v[m]), Bits(deviation)) << "p = " << p << " sample " << k;
        ASSERT_EQ(Bits(e_v[m]), Bits(e)) << "p = " << p << " sample " << k;
        for (int i = 0; i < p; ++i) ASSERT_EQ(Bits(s_v[i][m]), Bits(s[m][i])) << "p = " << p;
      }
    }
  }
}

TEST(Kernels, EachLaneOfTheFreeRunHasTheScalarRunsBits) {
  Draw draw(13);
  for (int p = 1; p <= 16; ++p) {
    std::vector<double> phi[kLanes], h[kLanes];
    for (int m = 0; m < kLanes; ++m) {
      for (int i = 0; i < p; ++i) {
        phi[m].push_back(draw(-1.0, 1.0) / p);
        h[m].push_back(draw(-1.0, 1.0));
      }
    }
    std::vector<Lanes4> phi_v(p), h_v(p);
    for (int i = 0; i < p; ++i) {
      phi_v[i] = Lanes4{phi[0][i], phi[1][i], phi[2][i], phi[3][i]};
      h_v[i] = Lanes4{h[0][i], h[1][i], h[2][i], h[3][i]};
    }
    for (int t = 0; t < 2000; ++t) {
      const Lanes4 s_v = FreeRunSample(phi_v.data(), p, h_v.data());
      for (int m = 0; m < kLanes; ++m) {
        const double s = FreeRunSample(phi[m].data(), p, h[m].data());
        ASSERT_EQ(Bits(s_v[m]), Bits(s)) << "p = " << p << " sample " << t << " lane " << m;
      }
    }
  }
}

TEST(Kernels, FourConsecutiveResidualsHaveTheScalarResidualsBits) {
  Draw draw(14);
  std::vector<double> x(3000);
  for (double& v : x) v = draw(-2.0, 2.0);
  for (int p = 1; p <= 16; ++p) {
    std::vector<double> phi(p);
    for (double& v : phi) v = draw(-1.0, 1.0);
    const double mean = draw(-0.5, 0.5);
    for (std::size_t t = p; t + kLanes <= x.size(); t += 3) {
      const double* xt = x.data() + t;
      const Lanes4 e_v = ArResidual<Lanes4>(
          [xt](int i) {
            Lanes4 v;
            std::memcpy(&v, xt - i, sizeof(v));
            return v;
          },
          phi.data(), p, mean);
      for (int m = 0; m < kLanes; ++m) {
        const double* xm = xt + m;
        const double e = ArResidual<double>([xm](int i) { return xm[-i]; }, phi.data(), p, mean);
        ASSERT_EQ(Bits(e_v[m]), Bits(e)) << "p = " << p << " t = " << t + m;
      }
    }
  }
}

TEST(Kernels, EachLaneOfTheModifiedWindowsHasTheScalarWindowsBits) {
  Draw draw(15);
  double s0[kLanes], s1[kLanes], s2[kLanes], sum[kLanes] = {};
  for (int m = 0; m < kLanes; ++m) s0[m] = draw(-5, 5), s1[m] = draw(-5, 5), s2[m] = draw(-5, 5);
  Lanes4 s0_v = Gather(s0), s1_v = Gather(s1), s2_v = Gather(s2), sum_v = {};
  for (int j = 0; j < 5000; ++j) {
    double a[kLanes], b[kLanes], c[kLanes], e[kLanes];
    for (int m = 0; m < kLanes; ++m)
      a[m] = draw(-1, 1), b[m] = draw(-1, 1), c[m] = draw(-1, 1), e[m] = draw(-1, 1);
    AddModifiedWindow(s0_v, s1_v, s2_v, &sum_v);
    SlideModifiedWindow(Gather(a), Gather(b), Gather(c), Gather(e), &s0_v, &s1_v, &s2_v);
    for (int m = 0; m < kLanes; ++m) {
      AddModifiedWindow(s0[m], s1[m], s2[m], &sum[m]);
      SlideModifiedWindow(a[m], b[m], c[m], e[m], &s0[m], &s1[m], &s2[m]);
      ASSERT_EQ(Bits(sum_v[m]), Bits(sum[m])) << "window " << j << " lane " << m;
      ASSERT_EQ(Bits(s0_v[m]), Bits(s0[m]));
      ASSERT_EQ(Bits(s1_v[m]), Bits(s1[m]));
      ASSERT_EQ(Bits(s2_v[m]), Bits(s2[m]));
    }
  }
}

// Sixteen consecutive outputs (four groups of four) against sixteen scalar sums, and the scalar
// sum against the convolution computed in long double: positive terms, so the relative error is
// at most the taps' count times 2^-53.
TEST(Kernels, EachCellOfTheGridConvolutionHasTheScalarSumsBits) {
  Draw draw(16);
  std::vector<double> x(400);
  for (double& v : x) v = draw(0.0, 1.0) < 0.2 ? 0.0 : draw(0.0, 1.0);
  for (int taps : {1, 2, 7, 42, 97}) {
    std::vector<double> weight(taps);
    for (double& w : weight) w = draw(0.0, 1.0);
    for (int k0 : {0, 1, taps / 2}) {
      const int k1 = taps - k0 / 2;
      for (int a = taps; a + 16 <= static_cast<int>(x.size()); a += 5) {
        Lanes4 sum_v[4];
        ConvolutionSums<Lanes4, 4>(
            [&](int k, int v) {
              Lanes4 cells;
              std::memcpy(&cells, x.data() + a + 4 * v - k, sizeof(cells));
              return cells;
            },
            weight.data(), k0, k1, sum_v);
        for (int c = 0; c < 16; ++c) {
          double sum;
          ConvolutionSums<double, 1>([&](int k, int) { return x[a + c - k]; }, weight.data(), k0,
                                     k1, &sum);
          ASSERT_EQ(Bits(sum_v[c / 4][c % 4]), Bits(sum)) << "taps " << taps << " cell " << a + c;
          long double direct = 0;
          for (int k = k0; k < k1; ++k)
            direct += static_cast<long double>(weight[k]) * x[a + c - k];
          ASSERT_NEAR(sum, static_cast<double>(direct),
                      (taps + 1) * std::ldexp(1.0, -53) * static_cast<double>(direct));
        }
      }
    }
  }
}

// The angle quantizer pads its grid with zeros so that every cell takes every tap: a tap on a
// zero adds +0, which leaves a non-negative partial sum's bits as they were, so a cell's sum over
// all taps of the padded input has the bits of its sum over the taps that land on the grid.
TEST(Kernels, TapsOnZeroPaddingLeaveTheGridConvolutionsBits) {
  Draw draw(17);
  for (int cells : {5, 33, 200}) {
    for (int taps : {3, 42}) {
      std::vector<double> weight(taps), x(cells), padded(cells + 2 * taps, 0.0);
      for (double& w : weight) w = draw(0.0, 1.0);
      for (int i = 0; i < cells; ++i) padded[taps + i] = x[i] = draw(0.0, 1.0);
      for (int first : {-taps, -taps / 2, 0, 3}) {
        for (int a = 0; a < cells; ++a) {
          const int k0 = std::max(0, a - first - cells + 1), k1 = std::min(taps, a - first + 1);
          double landing = 0.0, all = 0.0;
          if (k0 < k1)
            ConvolutionSums<double, 1>([&](int k, int) { return x[a - first - k]; }, weight.data(),
                                       k0, k1, &landing);
          ConvolutionSums<double, 1>(
              [&](int k, int) {
                const int i = a - first - k;
                return i >= -taps && i < cells + taps ? padded[taps + i] : 0.0;
              },
              weight.data(), 0, taps, &all);
          ASSERT_EQ(Bits(all), Bits(landing)) << cells << " " << taps << " " << first << " " << a;
        }
      }
    }
  }
}

TEST(Kernels, MulAddOfEachLaneIsTheScalarMulAdd) {
  Draw draw(16);
  for (int k = 0; k < 10000; ++k) {
    double a[kLanes], b[kLanes], c[kLanes];
    for (int m = 0; m < kLanes; ++m) a[m] = draw(-1, 1), b[m] = draw(-1, 1), c[m] = draw(-1, 1);
    const Lanes4 v = MulAdd(Gather(a), Gather(b), Gather(c));
    for (int m = 0; m < kLanes; ++m) ASSERT_EQ(Bits(v[m]), Bits(MulAdd(a[m], b[m], c[m])));
  }
}

}  // namespace
}  // namespace fogpipe::kernels
