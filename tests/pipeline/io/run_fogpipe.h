// Test helper: runs the fogpipe binary (path from the FOGPIPE_BINARY compile definition) and
// returns its exit code and standard output (stderr is merged in when asked).
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace fogpipe::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;
};

inline CommandResult RunFogpipe(const std::string& arguments, bool merge_stderr = false) {
  const std::string command =
      std::string(FOGPIPE_BINARY) + " " + arguments + (merge_stderr ? " 2>&1" : " 2>/dev/null");
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// Single-quotes a path for the shell.
inline std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace fogpipe::testing
