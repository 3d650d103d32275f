// The one "did you mean" rule (framework/util/suggest.h).
#include "framework/util/suggest.h"

#include <gtest/gtest.h>

namespace arcs {
namespace {

TEST(SuggestTest, EditDistanceCountsInsertionsDeletionsSubstitutions) {
  EXPECT_EQ(EditDistance("", ""), 0);
  EXPECT_EQ(EditDistance("abc", ""), 3);
  EXPECT_EQ(EditDistance("", "abc"), 3);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3);
  EXPECT_EQ(EditDistance("level", "levle"), 2);  // a transposition is two edits
  EXPECT_EQ(EditDistance("sdf_grid", "sdf_gird"), 2);
  EXPECT_EQ(EditDistance("a", "b"), 1);
}

TEST(SuggestTest, ThresholdIsTwoOrAThirdOfTheName) {
  const std::vector<std::string> c = {"iterations", "tau", "level"};
  EXPECT_EQ(NearestName("levle", c), "level");  // distance 2 <= max(2, 5/3)
  EXPECT_EQ(NearestName("tua", c), "tau");      // distance 2
  EXPECT_EQ(NearestName("xyz", c), "");         // distance 3 to "tau" > 2
  // A long name may be further off: max(2, 15/3) = 5.
  EXPECT_EQ(NearestName("iterationsxxxxx", {"iterations"}), "iterations");  // contained: 2
  EXPECT_EQ(NearestName("itterattionns", {"iterations"}), "iterations");    // distance 3 <= 13/3 = 4
  EXPECT_EQ(NearestName("itxxaxixxs", {"iterations"}), "");                 // distance 5 > max(2, 10/3)
}

TEST(SuggestTest, ContainmentCountsOnlyFromThreeCharacters) {
  EXPECT_EQ(NearestName("rfta2d", {"marching_cubes", "rfta"}), "rfta");
  EXPECT_EQ(NearestName("marching", {"rfta", "marching_squares"}), "marching_squares");
  // "n" is in every name with an n, but a one-letter key suggests nothing by it.
  EXPECT_EQ(NearestName("n", {"iterations_long_name"}), "");
  // ... while a short name one edit away still does.
  EXPECT_EQ(NearestName("m", {"n"}), "n");
}

TEST(SuggestTest, TiesGoToTheFirstCandidateAndNoneGivesNothing) {
  EXPECT_EQ(NearestName("ab", {"ac", "ad"}), "ac");
  EXPECT_EQ(NearestName("ab", {"ad", "ac"}), "ad");
  EXPECT_EQ(NearestName("anything", {}), "");
  EXPECT_EQ(DidYouMean("datasetz", {"name", "datasets"}), " (did you mean 'datasets'?)");
  EXPECT_EQ(DidYouMean("completely_unrelated_name", {"sdf_grid", "rfta"}), "");
}

}  // namespace
}  // namespace arcs
