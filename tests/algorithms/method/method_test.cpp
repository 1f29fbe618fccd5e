// Tests algorithms/method/method.cpp on simulated recordings in the paper's setting
// (fogpipe::simulation::PaperOptions: 1 h at 1 Hz, navigation-grade N, B, K, Q; known truth).
#include "algorithms/method/method.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "algorithms/method/tables.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"

namespace fogpipe::method {
namespace {

Eigen::VectorXd PaperRecording(std::uint64_t seed) {
  const simulation::SimulatedRecording rec =
      simulation::SimulateGyro(simulation::PaperOptions(seed));
  EXPECT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
  return rec.rate_rad_s;
}

TEST(Method, PrintsTables3And5OnPaperLikeData) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const MethodResult r = RunMethod(PaperRecording(seed), 1.0, MethodOptions());
    ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
    std::printf("seed %llu\n%s%s", static_cast<unsigned long long>(seed),
                FormatTable3(Table3(r)).c_str(), FormatTable5(Table5(r)).c_str());
  }
}

}  // namespace
}  // namespace fogpipe::method
