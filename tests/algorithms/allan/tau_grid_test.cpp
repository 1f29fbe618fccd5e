// Tests of algorithms/allan/tau_grid.{h,cpp}.
#include "algorithms/allan/tau_grid.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace fogpipe::allan {
namespace {

using V = std::vector<long long>;

TEST(AveragingFactors, OctaveIsPowersOfTwoUpToTheMaximum) {
  TauGridOptions o;
  EXPECT_EQ(AveragingFactors(o, 100), (V{1, 2, 4, 8, 16, 32, 64}));
  EXPECT_EQ(AveragingFactors(o, 64), (V{1, 2, 4, 8, 16, 32, 64}));
  EXPECT_TRUE(AveragingFactors(o, 0).empty());
}

TEST(AveragingFactors, DecadeIsRoundedLogSpacingWithoutDuplicates) {
  TauGridOptions o;
  o.kind = TauGridKind::kDecade;
  o.per_decade = 10;
  // round(10^(j/10)): 1 1.26 1.58 2.0 2.5 3.2 4.0 5.0 6.3 7.9 10 12.6 15.8 20 25 31.6 ...
  EXPECT_EQ(AveragingFactors(o, 40), (V{1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40}));
  o.per_decade = 3;
  EXPECT_EQ(AveragingFactors(o, 1000), (V{1, 2, 5, 10, 22, 46, 100, 215, 464, 1000}));
}

// Stable32's decade grid, as in its reports (e.g. allantools tests/phasedat/*_decade.txt:
// AF 1 2 4 10 20 40 100 200 for 1000 points).
TEST(AveragingFactors, Decade124IsStable32sDecadeGrid) {
  TauGridOptions o;
  o.kind = TauGridKind::kDecade124;
  EXPECT_EQ(AveragingFactors(o, 333), (V{1, 2, 4, 10, 20, 40, 100, 200}));
}

TEST(AveragingFactors, AllIsEveryFactor) {
  TauGridOptions o;
  o.kind = TauGridKind::kAll;
  EXPECT_EQ(AveragingFactors(o, 5), (V{1, 2, 3, 4, 5}));
}

TEST(AveragingFactors, ExplicitIsSortedDeduplicatedAndClipped) {
  TauGridOptions o;
  o.kind = TauGridKind::kExplicit;
  o.explicit_m = {7, 3, 3, 0, 100, 1};
  EXPECT_EQ(AveragingFactors(o, 50), (V{1, 3, 7}));
  std::string error;
  o.explicit_m.clear();
  EXPECT_FALSE(o.IsValid(&error));
}

// One spelling for every command: what `allan --taus` accepts, `run --taus` accepts too.
TEST(ParseTauGrid, AcceptsOctaveDecadeAllAndLog10AndNamesTheFormsOtherwise) {
  TauGridOptions g;
  std::string error;
  ASSERT_TRUE(ParseTauGrid("octave", &g, &error));
  EXPECT_EQ(g.kind, TauGridKind::kOctave);
  ASSERT_TRUE(ParseTauGrid("decade", &g, &error));
  EXPECT_EQ(g.kind, TauGridKind::kDecade);
  EXPECT_EQ(g.per_decade, 10);
  ASSERT_TRUE(ParseTauGrid("decade:5", &g, &error));
  EXPECT_EQ(g.per_decade, 5);
  ASSERT_TRUE(ParseTauGrid("all", &g, &error));
  EXPECT_EQ(g.kind, TauGridKind::kAll);
  ASSERT_TRUE(ParseTauGrid("log10", &g, &error));
  EXPECT_EQ(g.kind, TauGridKind::kAllantoolsLog10);
  EXPECT_EQ(AveragingFactors(g, 500000, 1000000), AllantoolsLog10Factors(1000000, 500000));
  for (const char* bad : {"decade:0", "decade:x", "decade:", "octaves", ""}) {
    EXPECT_FALSE(ParseTauGrid(bad, &g, &error)) << bad;
    EXPECT_NE(error.find("--taus"), std::string::npos) << bad;
  }
}

}  // namespace
}  // namespace fogpipe::allan
