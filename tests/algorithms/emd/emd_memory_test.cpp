// Heap use of Decompose (emd.h, "Memory"): at most (K + 4) N doubles including the input, K IMFs.
// Measured by interposing malloc/free/calloc/realloc in this test executable (glibc), so every
// allocation is counted (std::vector, Eigen) and the peak of the live heap is exact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "algorithms/emd/emd.h"
#include "tests/algorithms/emd/test_signals.h"

#if defined(__GLIBC__)
#include <malloc.h>

extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* p, size_t size);
void __libc_free(void* p);
}

namespace {
size_t g_live_bytes = 0;
size_t g_peak_bytes = 0;
void Count(void* p) {
  if (p == nullptr) return;
  g_live_bytes += malloc_usable_size(p);
  if (g_live_bytes > g_peak_bytes) g_peak_bytes = g_live_bytes;
}
void Uncount(void* p) {
  if (p != nullptr) g_live_bytes -= malloc_usable_size(p);
}
}  // namespace

extern "C" {
void* malloc(size_t size) {
  void* p = __libc_malloc(size);
  Count(p);
  return p;
}
void* calloc(size_t count, size_t size) {
  void* p = __libc_calloc(count, size);
  Count(p);
  return p;
}
void* realloc(void* old, size_t size) {
  Uncount(old);
  void* p = __libc_realloc(old, size);
  Count(p != nullptr ? p : (size == 0 ? nullptr : old));
  return p;
}
void free(void* p) {
  Uncount(p);
  __libc_free(p);
}
}
#endif

namespace fogpipe::emd {
namespace {

struct HeapUse {
  double peak_doubles = 0.0;  // Peak of the live heap during Decompose, above what was live before.
  double result_doubles = 0.0;  // Live after Decompose returned: the result.
  int num_imfs = 0;
};

HeapUse MeasureDecompose(const Eigen::VectorXd& x) {
  HeapUse use;
#if defined(__GLIBC__)
  const size_t before = g_live_bytes;
  g_peak_bytes = before;
  {
    const EmdResult r = Decompose(x, EmdOptions());
    use.num_imfs = r.summary.num_imfs;
    use.result_doubles = (g_live_bytes - before) / 8.0;
  }
  use.peak_doubles = (g_peak_bytes - before) / 8.0;
#endif
  return use;
}

// malloc_usable_size() counts what the allocator really hands out: vectors of 2^16 doubles above
// the mmap threshold are rounded up to whole 4096-byte pages (+512 doubles at most), and Eigen adds
// up to 64 bytes for alignment (+8 doubles).
double AllocatorRounding(int num_vectors) { return 520.0 * num_vectors; }
// The small parts of the result: 64 reserved IMF headers (128 doubles), the ImfInfo vector and the
// message (under 200 doubles for 20 IMFs).
constexpr double kSmallResultDoubles = 330.0;

void ExpectWithinBound(const Eigen::VectorXd& x, double expected_knot_doubles_per_sample) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "heap accounting needs glibc";
#endif
  const HeapUse use = MeasureDecompose(x);
  const double n = static_cast<double>(x.size());
  const int k = use.num_imfs;
  // The result: K IMFs and the residue.
  EXPECT_NEAR(use.result_doubles, (k + 1) * n, AllocatorRounding(k + 1) + kSmallResultDoubles);
  // The knots, the only other buffers, are live at the peak (the last IMF): 4 E doubles for E
  // maxima (emd.h), E = N / 3 on white noise, (N - 1) / 2 at most; 1/32 slack when growing.
  const double knots = use.peak_doubles - use.result_doubles;
  // Five knot arrays (two positions, two moments, one work), each possibly page-rounded.
  EXPECT_NEAR(knots, expected_knot_doubles_per_sample * n, 0.01 * n + AllocatorRounding(5));
  // The requirement, the caller's input x counted: (K + 4) N doubles. The worst case (an extremum
  // at every sample) reaches it up to the 4 x 2 mirrored-knot slots per envelope (a few dozen
  // doubles) and the allocator's page rounding.
  EXPECT_LE(use.peak_doubles + n,
            (k + 4) * n + 64.0 + AllocatorRounding(k + 1 + 5) + kSmallResultDoubles)
      << k << " IMFs";
}

TEST(EmdMemory, WhiteNoiseUsesOneAndAThirdNForTheKnots) {
  // A white-noise sample is a maximum with probability 1/3; sifting IMF 1 raises the count to
  // ~0.35 N, so the knot buffers end at ~0.36 N with slack: 4 x 0.36 = 1.44 N.
  ExpectWithinBound(testing::WhiteNoise(1 << 16, 8), 1.44);
}

TEST(EmdMemory, WorstCaseOfAnExtremumAtEverySampleStaysWithinTheBound) {
  // An alternating sequence has N / 2 - 1 maxima and as many minima: 4 E = 2 N doubles of knots.
  Eigen::VectorXd x = testing::WhiteNoise(1 << 16, 9);
  for (int i = 0; i < x.size(); ++i) x[i] = (i % 2 ? 1.0 : -1.0) * (2.0 + 0.1 * x[i]);
  ExpectWithinBound(x, 2.0);
}

// The knots sized for the first IMF (about N / 3 extrema per envelope in white noise) are sized
// down as the IMFs slow: at the end, where the kept IMFs make the peak, they are a small part.
TEST(EmdMemory, TheKnotsOfTheFirstImfAreNotHeldToTheEnd) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "heap accounting needs glibc";
#endif
  const Eigen::VectorXd x = testing::WhiteNoise(1 << 20, 11);
  const HeapUse use = MeasureDecompose(x);
  const double n = static_cast<double>(x.size());
  ASSERT_GE(use.num_imfs, 12);
  // Without the sizing down the knots at the peak are 1.44 N doubles (the test above).
  EXPECT_LT(use.peak_doubles - use.result_doubles, 0.1 * n);
}

// The streamed forms (emd.h): the sink form holds the remainder, one IMF buffer and the running
// sum besides the caller's input; the consuming form sifts in the input's own array, so its heap
// above the input is N doubles less.
TEST(EmdMemory, TheConsumingFormHoldsNDoublesLessThanTheSinkForm) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "heap accounting needs glibc";
#endif
  const Eigen::VectorXd x = testing::WhiteNoise(1 << 16, 10);
  const double n = static_cast<double>(x.size());
  const ImfSink sink = [](int, const Eigen::VectorXd&, const ImfInfo&) {};
  Eigen::VectorXd input = x;
  const size_t before = g_live_bytes;
  g_peak_bytes = before;
  { const EmdResult r = Decompose(input, EmdOptions(), sink); }
  const double sink_peak = (g_peak_bytes - before) / 8.0;
  g_peak_bytes = g_live_bytes;
  {
    const EmdResult r = Decompose(&input, EmdOptions(), sink, [&](Eigen::VectorXd* v) { *v = x; });
  }
  const double consuming_peak = (g_peak_bytes - before) / 8.0;
  // Remainder, IMF, sum and 1.44 N of knots (the test above) in the sink form.
  EXPECT_NEAR(sink_peak, 3 * n + 1.44 * n, 0.02 * n + AllocatorRounding(8));
  EXPECT_NEAR(consuming_peak, sink_peak - n, AllocatorRounding(8));
}

}  // namespace
}  // namespace fogpipe::emd
