// --memory-budget: how many recording axes may be in memory at once.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace fogpipe::graph {

/// Parses "2G", "512M", "64k", "1.5G", "1000000" (bytes; binary multiples K=2^10, M=2^20, G=2^30,
/// T=2^40; an optional trailing "B" or "iB" is accepted). nullopt for anything else or <= 0.
std::optional<std::uint64_t> ParseByteSize(const std::string& text);

/// The machine's physical memory (sysconf), 0 when the system does not say.
std::uint64_t PhysicalMemoryBytes();

/// The budget `--memory-budget auto` (the default) stands for: 80 % of SLURM_MEM_PER_NODE (MiB)
/// when Slurm set it (a job's --mem; at most 80 % of the physical memory), else half of the
/// physical memory (sysconf), else 2 GiB.
/// A fixed default would refuse long recordings on big machines (a 24 h record at 100 Hz needs
/// about 4 GiB) or overrun small ones.
std::uint64_t AutoMemoryBudgetBytes();

/// Bytes one axis of `num_samples` samples needs while it is analysed: the raw and preprocessed
/// signals, every IMF and the residue, their filtered versions, the method-1 and method-2 outputs
/// and work space, and the reference filters (filters/reference_filters.h: four output signals,
/// their tuning searches and Allan tables, kReferenceFilterDoubles per sample, measured as the
/// peak-memory difference of `run` with and without them). Estimated as (expected_imfs + 8 +
/// kReferenceFilterDoubles) x N x 8 bytes with expected_imfs = 2 log2(N) (+1 for the residue):
/// EMD of noise yields about log2(N) IMFs (Flandrin, Rilling & Goncalves 2004, "EMD as a filter
/// bank"), and every IMF is held twice (raw and filtered).
/// Saturates at UINT64_MAX instead of overflowing; never 0.
constexpr std::uint64_t kReferenceFilterDoubles = 52;
std::uint64_t BytesPerAxis(std::uint64_t num_samples, int max_imfs);

/// Memory the process needs whatever the recordings: the binary with its libraries, HDF5's and
/// TBB's own state (measured: 21 MiB peak RSS for a 2000-sample recording) and the results
/// writer's chunk buffers (pipeline/io/column_datasets.h: about 2 MiB per thread). Estimated as
/// 32 MiB + 2 MiB x threads.
std::uint64_t FixedBytes(int threads);

/// What the budget leaves for recordings in flight: budget - FixedBytes(threads), or 0.
std::uint64_t BytesForRecordings(std::uint64_t budget_bytes, int threads);

/// floor(budget / bytes_per_axis), at least 1. (The campaign refuses, before reading it, a
/// recording that alone needs more than the budget; see campaign.h.)
int AxesInFlight(std::uint64_t budget_bytes, std::uint64_t bytes_per_axis);

}  // namespace fogpipe::graph
