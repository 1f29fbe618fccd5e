#include "pipeline/graph/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <mutex>
#include <thread>

#include "pipeline/hdf5/atomic_output_file.h"

namespace fogpipe::graph {
namespace {

// Lock-free atomics are async-signal-safe (C++17 [support.signal]).
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void OnStopSignal(int signal_number) { g_stop_signal.store(signal_number); }

// A signal arrives; the flow graph stops at its next stage boundary, which a long decomposition
// or model stage can put minutes away. If the process is still running kStopGrace after the
// signal, the recordings in progress are abandoned as a kill would abandon them: their temporary
// outputs are removed, and the process ends with the interrupted exit code. Nothing is lost: a
// rerun finds no valid results for them and analyses them (results_reader.h).
constexpr std::chrono::milliseconds kStopGrace{1000};

void StopWatchdog() {
  while (g_stop_signal.load() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::this_thread::sleep_for(kStopGrace);
  hdf5::RemoveUncommittedTempFiles();
  static const char kMessage[] =
      "fogpipe: stopped; recordings still in progress were abandoned, the next run analyses "
      "them\n";
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  ::_exit(128 + g_stop_signal.load());
}

}  // namespace

void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  static std::once_flag watchdog;
  std::call_once(watchdog, [] { std::thread(StopWatchdog).detach(); });
}

bool StopRequested() { return g_stop_signal.load() != 0; }
int StopSignal() { return g_stop_signal.load(); }
int InterruptedExitCode() { return 128 + g_stop_signal.load(); }
void RequestStop(int signal_number) { g_stop_signal.store(signal_number); }
void ClearStopRequest() { g_stop_signal.store(0); }

}  // namespace fogpipe::graph
