#include "pipeline/graph/interrupt.h"

#include <atomic>
#include <csignal>

namespace fogpipe::graph {
namespace {

// Lock-free atomics are async-signal-safe (C++17 [support.signal]).
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void OnStopSignal(int signal_number) { g_stop_signal.store(signal_number); }

}  // namespace

void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool StopRequested() { return g_stop_signal.load() != 0; }
int StopSignal() { return g_stop_signal.load(); }
int InterruptedExitCode() { return 128 + g_stop_signal.load(); }
void RequestStop(int signal_number) { g_stop_signal.store(signal_number); }
void ClearStopRequest() { g_stop_signal.store(0); }

}  // namespace fogpipe::graph
