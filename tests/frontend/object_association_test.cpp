#include "frontend/object_association.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(ObjectAssociator, TrustsTrackedMaskIds) {
  ObjectAssociator a(AssociationParams{true, 0.3});
  const auto ids = a.associate({{4, 100}, {9, 50}}, {}, {});
  EXPECT_EQ(ids.at(4), 4);
  EXPECT_EQ(ids.at(9), 9);
}

TEST(ObjectAssociator, FollowsObjectsThroughRelabelledMasksByOverlap) {
  ObjectAssociator a(AssociationParams{false, 0.3});
  // Frame 0: two labels, no history: new objects 1 and 2.
  const auto first = a.associate({{7, 500}, {8, 400}}, {}, {});
  ASSERT_EQ(first.size(), 2u);
  const int car = first.at(7), van = first.at(8);
  EXPECT_NE(car, van);
  // Frame 1: the segmenter swapped its labels; the tracked points say which is which. Label 5 is new.
  const auto second = a.associate({{3, 480}, {4, 420}, {5, 100}},
                                  {{3, {{van, 40}, {car, 2}}}, {4, {{car, 45}}}}, {{car, 50}, {van, 50}});
  EXPECT_EQ(second.at(3), van);
  EXPECT_EQ(second.at(4), car);
  EXPECT_NE(second.at(5), car);
  EXPECT_NE(second.at(5), van);
}

TEST(ObjectAssociator, TooLittleOverlapStartsANewObjectAndEachObjectGoesToOneLabel) {
  ObjectAssociator a(AssociationParams{false, 0.5});
  const int car = a.associate({{1, 100}}, {}, {}).at(1);
  // Only 20 of 50 tracked points landed in label 2 (below 0.5): a new object. Label 3 and 4 both got
  // votes from the car; the one with more takes it.
  const auto ids = a.associate({{2, 100}, {3, 100}, {4, 100}}, {{2, {{car, 20}}}, {3, {{car, 30}}}, {4, {{car, 26}}}},
                               {{car, 50}});
  EXPECT_NE(ids.at(2), car);
  EXPECT_EQ(ids.at(3), car);
  EXPECT_NE(ids.at(4), car);
  EXPECT_THROW(ObjectAssociator(AssociationParams{false, 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
