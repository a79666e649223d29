// Command-line helpers (core/flags.h): splitting keeps empty pieces, so that callers can name a
// malformed list instead of reading past it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/flags.h"

namespace ddgi {
namespace {

using Pieces = std::vector<std::string>;

TEST(Split, KeepsEveryPieceEmptyOnesIncluded) {
  EXPECT_EQ(split("64,256", ','), (Pieces{"64", "256"}));
  EXPECT_EQ(split("1,,2", ','), (Pieces{"1", "", "2"}));
  EXPECT_EQ(split("a|", '|'), (Pieces{"a", ""}));
  EXPECT_EQ(split("", ','), (Pieces{""}));
  EXPECT_EQ(split("0,0,0/1,1,1/4,4,4", '/'), (Pieces{"0,0,0", "1,1,1", "4,4,4"}));
}

}  // namespace
}  // namespace ddgi
