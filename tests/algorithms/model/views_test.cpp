#include "algorithms/model/views.h"

#include <gtest/gtest.h>

namespace fogpipe::model {
namespace {

// The spellings reach `compare`'s outputs (JSON, results file, text), which scripts read.
TEST(ViewDomain, SpellingsAreTheOutputsAndParseBack) {
  const std::pair<ViewDomain, const char*> spellings[] = {{ViewDomain::kTau, "tau"},
                                                          {ViewDomain::kFrequency, "frequency"},
                                                          {ViewDomain::kTime, "time"},
                                                          {ViewDomain::kAux, "aux"}};
  for (const auto& [domain, text] : spellings) {
    EXPECT_STREQ(ToString(domain), text);
    EXPECT_EQ(ParseViewDomain(text), domain);
  }
  EXPECT_FALSE(ParseViewDomain("allan").has_value());
  EXPECT_FALSE(ParseViewDomain("").has_value());
}

}  // namespace
}  // namespace fogpipe::model
