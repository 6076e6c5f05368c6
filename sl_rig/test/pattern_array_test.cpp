#include <gtest/gtest.h>

#include <stdexcept>

#include "sl_rig/pattern_array.h"

using sl_projector::PatternArray;
using sl_projector::wrapAdd;

TEST(PatternArray, WrapStaysInOneToP)
{
  EXPECT_EQ(wrapAdd(4, 4, 4), 4);  // 8 wraps twice: 8 -> 4 (never 0)
  EXPECT_EQ(wrapAdd(4, 1, 4), 1);
  EXPECT_EQ(wrapAdd(3, 4, 4), 3);
  EXPECT_EQ(wrapAdd(1, 1, 4), 2);
  for (int a = 1; a <= 4; ++a)
    for (int b = 1; b <= 4; ++b)
    {
      EXPECT_GE(wrapAdd(a, b, 4), 1);
      EXPECT_LE(wrapAdd(a, b, 4), 4);
    }
}

TEST(PatternArray, DefaultConstructionFollowsGriffin)
{
  const PatternArray a;
  ASSERT_EQ(a.rows(), 16);
  ASSERT_EQ(a.cols(), 64);
  const std::string g43 = "4443442441433432431423422421413412411333233132232131231122212111";
  const std::string g42 = "4434241332312211";
  for (int c = 0; c < 64; ++c)
    EXPECT_EQ(a.value(0, c), g43[static_cast<size_t>(c)] - '0');
  // Row r+1 = row r + G(4,2)[r], wrapped into 1..4.
  for (int r = 0; r + 1 < 16; ++r)
    for (int c = 0; c < 64; ++c)
    {
      int expected = a.value(r, c) + (g42[static_cast<size_t>(r)] - '0');
      while (expected > 4)
        expected -= 4;
      EXPECT_EQ(a.value(r + 1, c), expected) << r << "," << c;
    }
  // Spot values worked out by hand: row 1 = row 0 + 4 = row 0; row 2 = row 1 + 4; row 3 = +3.
  EXPECT_EQ(a.value(1, 0), 4);
  EXPECT_EQ(a.value(3, 0), 3);  // 4 + 3 = 7 -> 3
  EXPECT_EQ(a.value(3, 3), 2);  // 3 + 3 = 6 -> 2
}

TEST(PatternArray, ColumnsWrapCyclically)
{
  const PatternArray a(4, 70);
  for (int c = 64; c < 70; ++c)
    EXPECT_EQ(a.value(2, c), a.value(2, c - 64));
  EXPECT_EQ(a.valueOrZero(-1, 0), 0);
  EXPECT_EQ(a.valueOrZero(0, 70), 0);
}

TEST(PatternArray, RejectsBadSizes)
{
  EXPECT_THROW(PatternArray(2, 64), std::invalid_argument);
  EXPECT_THROW(PatternArray(16, 1), std::invalid_argument);
  EXPECT_THROW(PatternArray(16, 64, 1), std::invalid_argument);
}
