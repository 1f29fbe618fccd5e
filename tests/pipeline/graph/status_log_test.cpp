// Tests of pipeline/graph/status_log.{h,cpp}: status lines stay whole when several processes
// append long lines to one log at once.
#include "pipeline/graph/status_log.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace fogpipe::graph {
namespace {

// 4 processes x 100 lines of 64 KiB (16 times PIPE_BUF, the size up to which POSIX promises
// atomic writes only for pipes) into one status.jsonl: all 400 lines parse and carry their whole
// message.
TEST(StatusLog, LinesOfConcurrentProcessesNeverInterleaveWhateverTheirLength) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("fogpipe_status_log_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "status.jsonl").string();
  const int processes = 4, lines = 100;
  const size_t length = 64 * 1024;
  for (int p = 0; p < processes; ++p) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      StatusLog log(path);
      FileOutcome outcome;
      outcome.status = FileStatus::kFailed;
      outcome.message = std::string(length, static_cast<char>('a' + p));
      for (int i = 0; i < lines; ++i) {
        outcome.file = "process" + std::to_string(p) + "_" + std::to_string(i) + ".h5";
        log.Append(outcome);
      }
      _exit(log.ok() ? 0 : 1);
    }
  }
  for (int p = 0; p < processes; ++p) {
    int status = 0;
    wait(&status);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  std::ifstream in(path);
  std::string line;
  int count = 0;
  while (std::getline(in, line)) {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << "line " << count << " is not whole JSON";
    const std::string file = j["file"], message = j["message"];
    ASSERT_EQ(message.size(), length) << file;
    EXPECT_EQ(message, std::string(length, message[0])) << file;
    // The log stores absolute paths: "/.../process<p>_<i>.h5".
    const std::string name = std::filesystem::path(file).filename().string();
    EXPECT_EQ(name[7], static_cast<char>(message[0] - 'a' + '0')) << file;
    ++count;
  }
  EXPECT_EQ(count, processes * lines);
  // A relative input is logged as absolute, so that `merge` run from another folder finds it.
  {
    StatusLog log(path);
    FileOutcome outcome;
    outcome.file = "relative/run.h5";
    log.Append(outcome);
  }
  std::ifstream again(path);
  std::string last;
  while (std::getline(again, line)) last = line;
  EXPECT_EQ(nlohmann::json::parse(last)["file"].get<std::string>(),
            (std::filesystem::current_path() / "relative/run.h5").string());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fogpipe::graph
