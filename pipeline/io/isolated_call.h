// Runs a piece of input handling in a forked child process with a wall-clock limit and an
// address-space limit, so that a crash (HDF5 1.10 dereferences corrupted global-heap sizes in
// H5HG_read and dies with SIGSEGV), a hang (a FIFO, a loop in damaged metadata) or a runaway
// allocation in one file's inspection becomes that file's named failure instead of the end of
// the whole process.
//
// The child is a copy of the caller at the moment of fork(2): locks the caller holds (the HDF5
// lock, pipeline/hdf5/hdf5_lock.h) are held by the child too, so the caller takes LockHdf5()
// BEFORE RunIsolated and the body uses HDF5 without taking it again. The child runs only the
// body (no TBB, no stdio) and leaves by _exit(2); it dies with its parent (PR_SET_PDEATHSIG) and
// never writes a core file.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace fogpipe::io {

struct IsolationLimits {
  /// Wall-clock limit of the child, seconds. The default, 10 s, suits metadata: inspecting it
  /// takes milliseconds, while damaged metadata can make HDF5 1.10 loop forever (a global-heap
  /// object of size 0). Reading samples needs a longer limit, given by the caller.
  double seconds = 10.0;
  /// Address space the child may add to what it inherits, bytes (default 1 GiB).
  std::uint64_t extra_memory_bytes = std::uint64_t{1} << 30;
  /// Polled every 0.1 s while the child runs; true kills the child (a stop request).
  std::function<bool()> stop;
};

struct IsolatedOutcome {
  enum class End { kExited, kSignalled, kTimedOut, kStopped, kNotStarted };
  End end = End::kNotStarted;
  int exit_code = 0;     ///< kExited: the body's return value
  int signal = 0;        ///< kSignalled: the signal that ended the child
  std::string output;    ///< bytes the body wrote to *output (binary-safe)
  std::string error;     ///< kNotStarted: why (fork or pipe failed)
  double seconds = 0.0;  ///< wall time the child ran

  /// "crashed with signal 11 (SIGSEGV)", "did not finish within 60 s", ... (not for kExited 0).
  std::string Describe(const IsolationLimits& limits) const;
  /// Stopped on request, or ended by SIGINT, SIGTERM or SIGHUP: a terminal's Ctrl-C reaches the
  /// whole process group, the child included. Never the file's fault.
  bool Interrupted() const;
};

/// Runs `body(&output)` in a child process and returns how it ended and what it wrote. The
/// body's return value becomes the child's exit code (keep it in 0..125); an exception escaping
/// the body ends the child with exit code 125.
IsolatedOutcome RunIsolated(const std::function<int(std::string* output)>& body,
                            const IsolationLimits& limits);

/// RunIsolated for a body that takes the HDF5 lock itself (pipeline/hdf5/hdf5_lock.h): the lock
/// is held across the fork, so that the child finds HDF5 idle, and the child releases its copy
/// before the body runs. Take no lock around it.
IsolatedOutcome RunIsolatedLockingHdf5(const std::function<int(std::string* output)>& body,
                                       const IsolationLimits& limits);

/// `summarize()` in a child process, for a command that prints one file's summary (`info`): a
/// damaged file that crashes or hangs the HDF5 library is reported by name, and the caller goes
/// on. Returns the text; throws std::runtime_error with the message of what `summarize` threw,
/// or naming `path` and how the child ended. `summarize` takes the HDF5 lock itself; take no
/// lock around it.
std::string SummarizeIsolated(const std::string& path,
                              const std::function<std::string()>& summarize);

}  // namespace fogpipe::io
