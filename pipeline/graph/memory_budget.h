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

/// Bytes one axis of `num_samples` samples needs while it is analysed: kDoublesPerSample x N x 8.
/// The method streams the components (method.h DecomposeAndModel with a scratch-file store,
/// io/spill_store.h), so the need no longer grows with the number of IMFs; what is held at once
/// is, by phase: during the EMD the running remainder (in the signal's own array: the signal
/// waits in the scratch file), the IMF being sifted, the running sum of the IMFs, the envelope
/// knots (sized down as the IMFs slow), the band limit's low-pass output and its right end
/// extension, and two IMFs with one more array each for their AR fits (about 11 N doubles; the
/// axis as read is released once preprocessed); during the filters the signal, the residue,
/// method 1 and two components with their filters; then method 2 beside the reference filters
/// (the Butterworth's GCV spectrum, about 3.5 N doubles while its FFT runs, is the largest part);
/// then the Allan tables of the seven outputs. Measured peak RSS minus FixedBytes(2), `run` with
/// 2 threads and default options at 8.64e6 samples (24 h at 100 Hz; docs/performance.md): 9.8 to
/// 12.9 doubles per sample over runs, depending on which reference filters overlap the GCV's
/// FFT; 20 leaves a margin for other signals' extrema counts and for options that keep more
/// (smoothing, stored filtered components). Saturates at UINT64_MAX instead of overflowing;
/// never 0.
constexpr std::uint64_t kDoublesPerSample = 20;
std::uint64_t BytesPerAxis(std::uint64_t num_samples);

/// What `run --model` adds to a recording of `num_samples` samples: the compensation it keeps for
/// its axes and each of the `aux_channels` it evaluates the model on (one signal each, read while
/// the compensation is computed; counted for the whole recording, which is conservative: they are
/// freed before the axes are read). Saturates at UINT64_MAX.
std::uint64_t ModelCompensationBytes(std::uint64_t num_samples, std::uint64_t aux_channels);

/// Memory the process needs whatever the recordings: the binary with its libraries, HDF5's and
/// TBB's own state, the reader's child process, the results writer's chunk buffers
/// (pipeline/io/column_datasets.h: about 2 MiB per thread), and what the heap keeps between
/// recordings. Measured: 26 MiB peak RSS for a 4000-sample recording, and 87.5 MiB of peak PSS
/// (the process and its readers) for a campaign of 1.8e5-sample recordings analysed one at a
/// time, 25 MiB of which their estimate covers. Estimated as 64 MiB + 2 MiB x threads.
std::uint64_t FixedBytes(int threads);

/// What the budget leaves for recordings in flight: budget - FixedBytes(threads), or 0.
std::uint64_t BytesForRecordings(std::uint64_t budget_bytes, int threads);

/// floor(budget / bytes_per_axis), at least 1. (The campaign refuses, before reading it, a
/// recording that alone needs more than the budget; see campaign.h.)
int AxesInFlight(std::uint64_t budget_bytes, std::uint64_t bytes_per_axis);

}  // namespace fogpipe::graph
