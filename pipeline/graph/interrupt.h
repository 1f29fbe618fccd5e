// Clean stop on SIGINT / SIGTERM: the handler only sets a flag (async-signal-safe); the flow graph
// polls it, stops feeding new recordings and abandons in-flight ones at the next stage boundary.
// A stage can take minutes on a long record, so a watchdog ends the process one second after the
// signal if it is still running, removing the temporary outputs of the recordings in progress
// (a rerun analyses them, as after a kill).
#pragma once

namespace fogpipe::graph {

/// Installs handlers for SIGINT and SIGTERM that record the signal, and the watchdog above.
/// Idempotent.
void InstallStopHandlers();
/// True once SIGINT or SIGTERM arrived (or RequestStop was called).
bool StopRequested();
/// The signal that asked to stop (SIGINT or SIGTERM), 0 if none.
int StopSignal();
/// Exit code for an interrupted run: 128 + signal (130 for SIGINT, 143 for SIGTERM).
int InterruptedExitCode();
/// Asks to stop as if `signal_number` had arrived (tests).
void RequestStop(int signal_number);
/// Forgets a stop request (tests; the next run in the same process).
void ClearStopRequest();

}  // namespace fogpipe::graph
