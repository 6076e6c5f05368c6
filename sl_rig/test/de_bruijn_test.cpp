#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "sl_rig/de_bruijn.h"

using sl_projector::deBruijnSequence;
using sl_projector::sequenceToString;

TEST(DeBruijn, ReproducesThePrototypeSequences)
{
  EXPECT_EQ(sequenceToString(deBruijnSequence(4, 3)),
            "4443442441433432431423422421413412411333233132232131231122212111");
  EXPECT_EQ(sequenceToString(deBruijnSequence(4, 2)), "4434241332312211");
}

// Every window of length n occurs exactly once, cyclically, for a range of P and n.
TEST(DeBruijn, EveryWindowOnceCyclically)
{
  for (int p = 2; p <= 6; ++p)
  {
    for (int n = 1; n <= 4; ++n)
    {
      const std::vector<int> s = deBruijnSequence(p, n);
      size_t expected = 1;
      for (int i = 0; i < n; ++i)
        expected *= static_cast<size_t>(p);
      ASSERT_EQ(s.size(), expected) << "P=" << p << " n=" << n;
      std::set<std::vector<int>> windows;
      for (size_t i = 0; i < s.size(); ++i)
      {
        std::vector<int> w;
        for (int k = 0; k < n; ++k)
        {
          const int v = s[(i + static_cast<size_t>(k)) % s.size()];
          ASSERT_GE(v, 1);
          ASSERT_LE(v, p);
          w.push_back(v);
        }
        windows.insert(w);
      }
      EXPECT_EQ(windows.size(), expected) << "P=" << p << " n=" << n;
    }
  }
}

TEST(DeBruijn, RejectsBadArguments)
{
  EXPECT_THROW(deBruijnSequence(1, 3), std::invalid_argument);
  EXPECT_THROW(deBruijnSequence(4, 0), std::invalid_argument);
  EXPECT_THROW(deBruijnSequence(64, 8), std::invalid_argument);
  EXPECT_THROW(sequenceToString({ 1, 12 }), std::invalid_argument);
}
