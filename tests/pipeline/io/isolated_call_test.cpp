// Tests of pipeline/io/isolated_call: how a child process ends is reported as data, and a
// terminal's Ctrl-C (which reaches the child too) is an interruption, never a crash of the file.
#include "pipeline/io/isolated_call.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <string>

namespace fogpipe::io {
namespace {

TEST(RunIsolated, ReturnsTheChildsOutputAndExitCode) {
  const IsolatedOutcome o = RunIsolated(
      [](std::string* out) {
        *out = std::string("binary\0safe", 11);
        return 7;
      },
      IsolationLimits());
  EXPECT_EQ(o.end, IsolatedOutcome::End::kExited);
  EXPECT_EQ(o.exit_code, 7);
  EXPECT_EQ(o.output, std::string("binary\0safe", 11));
  EXPECT_FALSE(o.Interrupted());
}

TEST(RunIsolated, ACrashIsASignalAndNotAnInterruption) {
  const IsolatedOutcome o = RunIsolated(
      [](std::string*) {
        std::raise(SIGSEGV);
        return 0;
      },
      IsolationLimits());
  EXPECT_EQ(o.end, IsolatedOutcome::End::kSignalled);
  EXPECT_EQ(o.signal, SIGSEGV);
  EXPECT_FALSE(o.Interrupted());
  EXPECT_NE(o.Describe(IsolationLimits()).find("SIGSEGV"), std::string::npos);
}

TEST(RunIsolated, SigintAndSigtermInTheChildAreInterruptions) {
  for (int sig : {SIGINT, SIGTERM}) {
    const IsolatedOutcome o = RunIsolated(
        [sig](std::string*) {
          std::raise(sig);
          return 0;
        },
        IsolationLimits());
    EXPECT_EQ(o.end, IsolatedOutcome::End::kSignalled) << sig;
    EXPECT_TRUE(o.Interrupted()) << sig;
  }
}

TEST(RunIsolated, AChildThatDoesNotFinishIsStoppedAtItsTimeLimit) {
  IsolationLimits limits;
  limits.seconds = 0.5;
  const IsolatedOutcome o = RunIsolated(
      [](std::string*) {
        ::sleep(30);
        return 0;
      },
      limits);
  EXPECT_EQ(o.end, IsolatedOutcome::End::kTimedOut);
  EXPECT_FALSE(o.Interrupted());
  EXPECT_LT(o.seconds, 5.0);
}

TEST(RunIsolated, AStopRequestEndsTheChildAsAnInterruption) {
  IsolationLimits limits;
  limits.stop = [] { return true; };
  const IsolatedOutcome o = RunIsolated(
      [](std::string*) {
        ::sleep(30);
        return 0;
      },
      limits);
  EXPECT_EQ(o.end, IsolatedOutcome::End::kStopped);
  EXPECT_TRUE(o.Interrupted());
}

}  // namespace
}  // namespace fogpipe::io
