#include "algorithms/common/catalog.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace fogpipe::catalog {
namespace {

TEST(Catalog, ListsTheFourteenTermsWithTheirFixedNames) {
  const std::vector<std::string> expected = {"white",
                                             "quantization",
                                             "angle_quantizer",
                                             "bias_instability",
                                             "rate_random_walk",
                                             "rate_ramp",
                                             "gauss_markov",
                                             "sinusoid",
                                             "narrow_band",
                                             "temperature",
                                             "temperature_rate",
                                             "bias_step",
                                             "bias_levels",
                                             "warmup"};
  ASSERT_EQ(AllTerms().size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(ToString(AllTerms()[i]), expected[i]);
}

TEST(Catalog, EveryNameParsesBackToItsTerm) {
  for (Term term : AllTerms()) EXPECT_EQ(ParseTerm(ToString(term)), term);
  EXPECT_EQ(ParseTerm("Bias_Instability"), std::nullopt);
  EXPECT_EQ(ParseTerm("flicker"), std::nullopt);
  EXPECT_EQ(ParseTerm(""), std::nullopt);
}

TEST(Catalog, OnlyTheFiveEffectsAreDeterministicAndOnlyTheThermalOnesNeedTemperature) {
  std::set<std::string> deterministic;
  std::set<std::string> thermal;
  for (Term term : AllTerms()) {
    if (KindOf(term) == TermKind::kDeterministic) deterministic.insert(ToString(term));
    if (NeedsTemperature(term)) thermal.insert(ToString(term));
  }
  EXPECT_EQ(deterministic, (std::set<std::string>{"temperature", "temperature_rate", "bias_step",
                                                  "bias_levels", "warmup"}));
  EXPECT_EQ(thermal, (std::set<std::string>{"temperature", "temperature_rate"}));
}

}  // namespace
}  // namespace fogpipe::catalog
