// EncodeChunk (pipeline/io/column_datasets.h) on one full chunk of 65536 rows of white noise
// (the content of a fast IMF: the hardest to compress), and on an edge chunk of 40000 rows
// padded to 65536. Arguments: storage (0 float64, 1 float32), deflate level (0 or 1).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "pipeline/io/column_datasets.h"

namespace {

std::vector<double> Noise(std::size_t n) {
  std::mt19937_64 rng(20261121);
  std::vector<double> x(n);
  // Box-Muller on explicit uniforms (deterministic across standard libraries).
  for (std::size_t i = 0; i < n; ++i) {
    const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    x[i] = 1e-5 * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  return x;
}

void Encode(benchmark::State& state, std::size_t rows) {
  const std::vector<double> x = Noise(rows);
  fogpipe::io::ColumnStorage storage;
  storage.type =
      state.range(0) ? fogpipe::hdf5::StorageType::kFloat32 : fogpipe::hdf5::StorageType::kFloat64;
  storage.deflate_level = static_cast<int>(state.range(1));
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::vector<unsigned char> chunk = fogpipe::io::EncodeChunk(x.data(), rows, storage);
    bytes = chunk.size();
    benchmark::DoNotOptimize(chunk.data());
  }
  state.counters["stored_bytes"] = static_cast<double>(bytes);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * rows * sizeof(double)));
}

void BM_EncodeFullChunk(benchmark::State& state) { Encode(state, 65536); }
void BM_EncodeEdgeChunk(benchmark::State& state) { Encode(state, 40000); }

BENCHMARK(BM_EncodeFullChunk)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EncodeEdgeChunk)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
