#include "pipeline/io/isolated_call.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "pipeline/hdf5/hdf5_lock.h"

namespace fogpipe::io {
namespace {

/// The caller's virtual memory size in bytes (/proc/self/statm), 0 when unknown. The child's
/// address-space limit is counted on top of it: a fork inherits every mapping of the parent.
std::uint64_t VirtualMemoryBytes() {
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm == nullptr) return 0;
  unsigned long long pages = 0;
  const int read = std::fscanf(statm, "%llu", &pages);
  std::fclose(statm);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  return read == 1 && page > 0 ? pages * static_cast<std::uint64_t>(page) : 0;
}

bool WriteAll(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] void RunChild(const std::function<int(std::string*)>& body, int fd,
                           std::uint64_t address_space) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  if (address_space > 0) {
    const rlimit as{address_space, address_space};
    ::setrlimit(RLIMIT_AS, &as);
  }
  // The parent's stop handlers only set a flag the child never polls: restore the defaults so
  // that a signal sent to the process group ends the child at once.
  ::signal(SIGINT, SIG_DFL);
  ::signal(SIGTERM, SIG_DFL);
  int code = 125;
  std::string output;
  try {
    code = body(&output);
  } catch (...) {
    code = 125;
  }
  WriteAll(fd, output);
  ::_exit(code);
}

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::string IsolatedOutcome::Describe(const IsolationLimits& limits) const {
  std::ostringstream out;
  switch (end) {
    case End::kExited:
      out << "ended with exit code " << exit_code;
      break;
    case End::kSignalled:
      out << "crashed with signal " << signal << " (SIG"
          << (sigabbrev_np(signal) ? sigabbrev_np(signal) : "?") << ")";
      break;
    case End::kTimedOut:
      out << "did not finish within " << limits.seconds << " s";
      break;
    case End::kStopped:
      out << "was stopped by a stop request";
      break;
    case End::kNotStarted:
      out << "could not be started: " << error;
      break;
  }
  return out.str();
}

IsolatedOutcome RunIsolated(const std::function<int(std::string* output)>& body,
                            const IsolationLimits& limits) {
  IsolatedOutcome outcome;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    outcome.error = std::string("pipe: ") + std::strerror(errno);
    return outcome;
  }
  const std::uint64_t address_space =
      limits.extra_memory_bytes > 0 ? VirtualMemoryBytes() + limits.extra_memory_bytes : 0;
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) {
    outcome.error = std::string("fork: ") + std::strerror(errno);
    ::close(fds[0]);
    ::close(fds[1]);
    return outcome;
  }
  if (pid == 0) {
    ::close(fds[0]);
    RunChild(body, fds[1], address_space);
  }
  ::close(fds[1]);
  bool killed = false;
  char buffer[1 << 16];
  for (;;) {
    if (limits.stop && limits.stop()) {
      outcome.end = IsolatedOutcome::End::kStopped;
      killed = true;
      break;
    }
    if (Since(start) > limits.seconds) {
      outcome.end = IsolatedOutcome::End::kTimedOut;
      killed = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, 100);
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // EOF: the child has exited (or closed the pipe by dying)
    outcome.output.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (killed) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  outcome.seconds = Since(start);
  if (killed) {
    outcome.output.clear();
    return outcome;
  }
  if (WIFSIGNALED(status)) {
    outcome.end = IsolatedOutcome::End::kSignalled;
    outcome.signal = WTERMSIG(status);
  } else {
    outcome.end = IsolatedOutcome::End::kExited;
    outcome.exit_code = WEXITSTATUS(status);
  }
  return outcome;
}

bool IsolatedOutcome::Interrupted() const {
  return end == End::kStopped ||
         (end == End::kSignalled && (signal == SIGINT || signal == SIGTERM || signal == SIGHUP));
}

IsolatedOutcome RunIsolatedLockingHdf5(const std::function<int(std::string* output)>& body,
                                       const IsolationLimits& limits) {
  auto lock = hdf5::LockHdf5();
  return RunIsolated(
      [&](std::string* output) {
        lock.unlock();
        return body(output);
      },
      limits);
}

std::string SummarizeIsolated(const std::string& path,
                              const std::function<std::string()>& summarize) {
  constexpr int kReadError = 1;
  const IsolationLimits limits;
  const IsolatedOutcome outcome = RunIsolatedLockingHdf5(
      [&](std::string* out) {
        try {
          *out = summarize();
          return 0;
        } catch (const std::exception& e) {
          *out = e.what();
          return kReadError;
        }
      },
      limits);
  using End = IsolatedOutcome::End;
  if (outcome.end == End::kExited && outcome.exit_code == 0) return outcome.output;
  if (outcome.end == End::kExited && outcome.exit_code == kReadError) {
    throw std::runtime_error(outcome.output);
  }
  if (outcome.Interrupted()) throw std::runtime_error(path + ": interrupted");
  throw std::runtime_error(path + ": reading it, the HDF5 library " + outcome.Describe(limits) +
                           " (damaged HDF5 metadata); the failure was contained in a child "
                           "process");
}

}  // namespace fogpipe::io
