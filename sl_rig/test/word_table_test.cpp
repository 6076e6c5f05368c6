#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "sl_rig/word_table.h"

using sl_projector::GridPos;
using sl_projector::PatternArray;
using sl_projector::WordTable;

namespace
{
// Counts interior elements whose word is unique by brute force (independent of WordTable).
int bruteForceUnique(const PatternArray& a)
{
  int unique = 0;
  for (int r = 1; r + 1 < a.rows(); ++r)
    for (int c = 1; c + 1 < a.cols(); ++c)
    {
      int same = 0;
      for (int r2 = 1; r2 + 1 < a.rows(); ++r2)
        for (int c2 = 1; c2 + 1 < a.cols(); ++c2)
          same += a.value(r, c) == a.value(r2, c2) && a.value(r - 1, c) == a.value(r2 - 1, c2) &&
                  a.value(r, c - 1) == a.value(r2, c2 - 1) && a.value(r + 1, c) == a.value(r2 + 1, c2) &&
                  a.value(r, c + 1) == a.value(r2, c2 + 1);
      unique += same == 1;
    }
  return unique;
}
}  // namespace

TEST(WordTable, DefaultArrayHas868UniqueWords)
{
  const PatternArray a(16, 64);
  EXPECT_EQ(bruteForceUnique(a), 868);
  const WordTable t(a);
  EXPECT_EQ(t.size(), 868);
}

TEST(WordTable, LargestArrayOf17By66Has960UniqueWords)
{
  const PatternArray a(17, 66);
  EXPECT_EQ(bruteForceUnique(a), 960);
  EXPECT_EQ(WordTable(a).size(), 960);
}

TEST(WordTable, LookupAndInverseRoundTripEverywhere)
{
  for (auto size : { std::pair<int, int>{ 16, 64 }, { 10, 30 }, { 18, 66 }, { 3, 3 } })
  {
    const PatternArray a(size.first, size.second);
    const WordTable t(a);
    for (int r = 0; r < a.rows(); ++r)
      for (int c = 0; c < a.cols(); ++c)
      {
        const int w = t.wordAt(r, c);
        const bool interior = r > 0 && c > 0 && r + 1 < a.rows() && c + 1 < a.cols();
        if (!interior)
        {
          EXPECT_EQ(w, -1);
          continue;
        }
        ASSERT_GE(w, 0);
        const GridPos p = t.lookup(w);
        EXPECT_EQ(p.row, r);
        EXPECT_EQ(p.col, c);
        EXPECT_EQ(t.lookup(a.value(r, c), a.value(r - 1, c), a.value(r, c - 1), a.value(r + 1, c), a.value(r, c + 1)),
                  p);
      }
  }
}

TEST(WordTable, UnknownWordsAndBadSymbolsGiveInvalid)
{
  const PatternArray a;
  const WordTable t(a);
  EXPECT_EQ(t.encode(0, 1, 1, 1, 1), -1);
  EXPECT_EQ(t.encode(1, 1, 5, 1, 1), -1);
  EXPECT_FALSE(t.lookup(-1).valid());
  EXPECT_FALSE(t.lookup(4 * 4 * 4 * 4 * 4).valid());
  EXPECT_FALSE(t.lookup(1, 1, 5, 1, 1).valid());
  // 1024 possible words, 868 used: the rest must not decode.
  int valid = 0;
  for (int w = 0; w < 1024; ++w)
    valid += t.lookup(w).valid();
  EXPECT_EQ(valid, 868);
}

TEST(WordTable, RefusesNonUniqueConfigurations)
{
  // 19 rows: rows 1 and 17 repeat the same G(4,2) window, so words repeat.
  try
  {
    const PatternArray a(19, 64);
    const WordTable t(a);
    FAIL() << "expected std::invalid_argument";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("duplicate words"), std::string::npos) << e.what();
  }
  // 68 columns: columns repeat the G(4,3) windows.
  EXPECT_THROW(WordTable(PatternArray(16, 68)), std::invalid_argument);
  // The table keeps its own copy: it stays valid after the array is gone.
  std::unique_ptr<WordTable> t;
  {
    const PatternArray a(16, 64);
    t.reset(new WordTable(a));
  }
  EXPECT_EQ(t->wordAt(5, 5) >= 0, true);
  EXPECT_EQ(t->lookup(t->wordAt(5, 5)), (GridPos{ 5, 5 }));
}
