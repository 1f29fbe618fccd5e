#include "pipeline/io/isolated_reader.h"

#include <cstring>
#include <new>
#include <type_traits>

#include "pipeline/hdf5/hdf5_lock.h"

namespace fogpipe::io {
namespace {

// The child's exit codes.
constexpr int kOk = 0;
constexpr int kRecordingProblem = 1;  ///< output: kind '\n' problem
constexpr int kOtherError = 2;        ///< output: what()
constexpr int kOutOfMemory = 3;

/// Runs `body` (which may throw RecordingError) in a child and turns every way it can end
/// badly into a RecordingError naming `path` and `what` the child was doing.
void RunReaderChild(const std::string& path, const std::string& what,
                    const std::function<void(std::string*)>& body, const IsolationLimits& limits,
                    std::string* output) {
  auto child = [&](std::string* out) {
    try {
      body(out);
      return kOk;
    } catch (const RecordingError& e) {
      *out = e.kind() + "\n" + e.problem();
      return kRecordingProblem;
    } catch (const std::bad_alloc&) {
      out->clear();
      return kOutOfMemory;
    } catch (const std::exception& e) {
      *out = e.what();
      return kOtherError;
    }
  };
  IsolatedOutcome outcome;
  {
    auto lock = hdf5::LockHdf5();  // inherited by the child; see isolated_call.h
    outcome = RunIsolated(child, limits);
  }
  using End = IsolatedOutcome::End;
  if (outcome.end == End::kExited && outcome.exit_code == kOk) {
    *output = std::move(outcome.output);
    return;
  }
  if (outcome.end == End::kExited && outcome.exit_code == kRecordingProblem) {
    const std::size_t newline = outcome.output.find('\n');
    throw RecordingError(outcome.output.substr(0, newline), path,
                         newline == std::string::npos ? "" : outcome.output.substr(newline + 1));
  }
  if (outcome.end == End::kExited && outcome.exit_code == kOtherError) {
    throw RecordingError(error_kind::kCorruptFile, path, what + ": " + outcome.output);
  }
  if (outcome.end == End::kExited && outcome.exit_code == kOutOfMemory) {
    throw RecordingError(error_kind::kReaderOutOfMemory, path,
                         what + " needed more than the " +
                             std::to_string(limits.extra_memory_bytes >> 20) +
                             " MiB allowed (a damaged or implausible file); not analysed");
  }
  if (outcome.end == End::kSignalled) {
    throw RecordingError(error_kind::kReaderCrashed, path,
                         "the HDF5 library " + outcome.Describe(limits) + " while " + what +
                             " (damaged HDF5 metadata); the crash was contained in a child "
                             "process, the file is not analysed");
  }
  if (outcome.end == End::kTimedOut) {
    throw RecordingError(error_kind::kReaderTimeout, path,
                         what + " " + outcome.Describe(limits) +
                             " (damaged metadata that loops, or a file that blocks); stopped");
  }
  if (outcome.end == End::kStopped) {
    throw RecordingError(error_kind::kInterrupted, path, what + " interrupted by a stop request");
  }
  throw RecordingError(error_kind::kUnreadableFile, path, what + " " + outcome.Describe(limits));
}

}  // namespace

IsolationLimits DataReadLimits() {
  IsolationLimits limits;
  limits.seconds = 600.0;
  return limits;
}

RecordingInfo InspectRecordingIsolated(const std::string& path, const IsolationLimits& limits) {
  std::string ignored;
  RunReaderChild(
      path, "reading its metadata", [&](std::string*) { RecordingReader reader(path); }, limits,
      &ignored);
  auto lock = hdf5::LockHdf5();
  RecordingReader reader(path);
  return reader.info();
}

Eigen::VectorXd ReadAxisRadPerSecondIsolated(const RecordingInfo& info, const std::string& axis,
                                             const ReadOptions& options, ReadReport* report,
                                             const IsolationLimits& limits) {
  const std::string& path = info.path;
  static_assert(std::is_trivially_copyable<ReadReport>::value,
                "the report crosses the pipe as bytes (the child is this same binary)");
  std::string output;
  IsolationLimits read_limits = limits;
  auto read = [&](std::string* out) {
    RecordingReader reader(path);
    ReadReport local;
    const Eigen::VectorXd x = reader.ReadAxisRadPerSecond(axis, options, &local);
    out->assign(reinterpret_cast<const char*>(&local), sizeof(local));
    out->append(reinterpret_cast<const char*>(x.data()),
                static_cast<std::size_t>(x.size()) * sizeof(double));
  };
  // The axis itself is allowed on top of the limit, twice (the vector and the pipe's copy).
  read_limits.extra_memory_bytes += 2 * static_cast<std::uint64_t>(info.samples) * sizeof(double);
  RunReaderChild(path, "reading /rate axis '" + axis + "'", read, read_limits, &output);
  if (output.size() < sizeof(ReadReport) ||
      (output.size() - sizeof(ReadReport)) % sizeof(double) != 0) {
    throw RecordingError(error_kind::kUnreadableFile, path,
                         "reading /rate axis '" + axis + "': the reader process returned " +
                             std::to_string(output.size()) + " bytes");
  }
  ReadReport local;
  std::memcpy(&local, output.data(), sizeof(local));
  const auto n =
      static_cast<Eigen::Index>((output.size() - sizeof(ReadReport)) / sizeof(double));
  Eigen::VectorXd x(n);
  std::memcpy(x.data(), output.data() + sizeof(ReadReport), static_cast<std::size_t>(n) * 8);
  if (report) *report = local;
  return x;
}

}  // namespace fogpipe::io
