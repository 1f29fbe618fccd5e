// graph::WorkProgress: the wrapped ForEach runs every body once and counts it, steps and stages
// are printed in run's style, and a null stream prints nothing.
#include "pipeline/graph/progress.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

namespace fogpipe::graph {
namespace {

std::string Contents(std::FILE* file) {
  std::fflush(file);
  std::rewind(file);
  std::string text;
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), file)) > 0) text.append(buffer, n);
  return text;
}

TEST(WorkProgress, CountingRunsEveryBodyOnceAndPrintsTheStepAndTheStageOnATerminal) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  std::vector<int> runs(7, 0);
  {
    WorkProgress progress("sweep rec.h5", file, /*redraw=*/true);
    progress.Step("table 1/1 (axis x, 10 sifts)");
    const ForEach serial = [](int n, const std::function<void(int)>& body) {
      for (int i = 0; i < n; ++i) body(i);
    };
    progress.Counting(serial)(7, [&](int i) { ++runs[i]; });
    progress.Finish();
  }
  EXPECT_EQ(runs, std::vector<int>(7, 1));
  const std::string text = Contents(file);
  EXPECT_NE(text.find("\r\033[Ksweep rec.h5: table 1/1 (axis x, 10 sifts)  elapsed 0s"),
            std::string::npos)
      << text;
  // The stage's end is always drawn on a terminal.
  EXPECT_NE(text.find("sweep rec.h5: table 1/1 (axis x, 10 sifts), stage 1 [7/7]  elapsed"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.back(), '\n');
  std::fclose(file);
}

TEST(WorkProgress, LogLinesAreWholeLinesAndAnEmptyForEachRunsSerially) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  int sum = 0;
  WorkProgress progress("compare rec.h5", file, /*redraw=*/false);
  progress.Step("axis y: reading");
  progress.Counting(ForEach{})(4, [&](int i) { sum += i; });
  progress.Finish();
  EXPECT_EQ(sum, 6);
  EXPECT_EQ(Contents(file), "compare rec.h5: axis y: reading  elapsed 0s\n");
  std::fclose(file);
}

TEST(WorkProgress, PrintsNothingWithoutAStream) {
  int count = 0;
  WorkProgress progress("sweep rec.h5", nullptr, true);
  progress.Step("reading");
  progress.Counting(ForEach{})(3, [&](int) { ++count; });
  EXPECT_EQ(count, 3);
}

}  // namespace
}  // namespace fogpipe::graph
