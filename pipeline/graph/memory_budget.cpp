#include "pipeline/graph/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace fogpipe::graph {

std::uint64_t PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0
             ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_size)
             : 0;
}

std::uint64_t AutoMemoryBudgetBytes() {
  const std::uint64_t physical = PhysicalMemoryBytes();
  if (const char* slurm = std::getenv("SLURM_MEM_PER_NODE")) {
    // A job's --mem in MiB: a whole number. Anything else is ignored, and no job can hold more
    // than the machine, so the budget never exceeds 80 % of the physical memory either.
    char* end = nullptr;
    const unsigned long long mib = std::strtoull(slurm, &end, 10);
    if (end != slurm && *end == '\0' && mib > 0 && mib < (1ull << 40)) {
      std::uint64_t bytes = mib * 1048576ull / 5 * 4;
      if (physical > 0) bytes = std::min(bytes, physical / 5 * 4);
      return bytes;
    }
  }
  if (physical > 0) return physical / 2;
  return std::uint64_t{2} << 30;
}

std::optional<std::uint64_t> ParseByteSize(const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  std::string suffix = text.substr(used);
  for (char& c : suffix) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (suffix.size() >= 2 && suffix.compare(suffix.size() - 2, 2, "IB") == 0) {
    suffix.resize(suffix.size() - 2);
  } else if (suffix.size() >= 2 && suffix.back() == 'B') {
    suffix.pop_back();
  } else if (suffix == "B") {
    suffix.clear();
  }
  double scale = 1.0;
  if (suffix == "K") {
    scale = 1024.0;
  } else if (suffix == "M") {
    scale = 1024.0 * 1024.0;
  } else if (suffix == "G") {
    scale = 1024.0 * 1024.0 * 1024.0;
  } else if (suffix == "T") {
    scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  } else if (!suffix.empty()) {
    return std::nullopt;
  }
  const double bytes = value * scale;
  if (!std::isfinite(bytes) || bytes < 1.0 || bytes > 1.8e19) return std::nullopt;
  return static_cast<std::uint64_t>(bytes);
}

std::uint64_t BytesPerAxis(std::uint64_t num_samples) {
  std::uint64_t bytes = 0;
  if (__builtin_mul_overflow(kDoublesPerSample * 8, std::max<std::uint64_t>(num_samples, 1),
                             &bytes)) {
    return UINT64_MAX;  // saturates: never admitted, never 0
  }
  return bytes;
}

std::uint64_t ModelCompensationBytes(std::uint64_t num_samples, std::uint64_t aux_channels) {
  std::uint64_t bytes = 0;
  if (aux_channels > UINT64_MAX / sizeof(double) - 1 ||
      __builtin_mul_overflow((1 + aux_channels) * sizeof(double), num_samples, &bytes))
    return UINT64_MAX;
  return bytes;
}

std::uint64_t FixedBytes(int threads) {
  constexpr std::uint64_t kMiB = 1ull << 20;
  return 64 * kMiB + 2 * kMiB * static_cast<std::uint64_t>(std::max(1, threads));
}

std::uint64_t BytesForRecordings(std::uint64_t budget_bytes, int threads) {
  const std::uint64_t fixed = FixedBytes(threads);
  return budget_bytes > fixed ? budget_bytes - fixed : 0;
}

int AxesInFlight(std::uint64_t budget_bytes, std::uint64_t bytes_per_axis) {
  const std::uint64_t n = budget_bytes / std::max<std::uint64_t>(bytes_per_axis, 1);
  return static_cast<int>(std::clamp<std::uint64_t>(n, 1, 1 << 20));
}

}  // namespace fogpipe::graph
