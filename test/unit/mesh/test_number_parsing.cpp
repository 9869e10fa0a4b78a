// The strict number parser shared by the text readers: the whole token or nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "deformation_enrichment/number_parsing.hpp"

namespace de = deformation_enrichment;

TEST(NumberParsing, IntegersWithOptionalSign) {
  EXPECT_EQ(de::parseInteger("12"), 12L);
  EXPECT_EQ(de::parseInteger("+12"), 12L);
  EXPECT_EQ(de::parseInteger("-3"), -3L);
  EXPECT_EQ(de::parseInteger("9223372036854775807"), std::numeric_limits<long>::max());
  for (const char* bad : {"", "+", "-", "+-1", "++1", " 1", "1 ", "1x", "1.0", "1e3", "0x10",
                          "9223372036854775808", "-9223372036854775809"})
    EXPECT_FALSE(de::parseInteger(bad)) << "'" << bad << "'";
}

TEST(NumberParsing, RealsAsStrtodReadsThemButWholeTokenOnly) {
  EXPECT_EQ(de::parseReal("1"), 1.0);
  EXPECT_EQ(de::parseReal("-2.5e-3"), -2.5e-3);
  EXPECT_EQ(de::parseReal("+.5"), 0.5);
  EXPECT_EQ(de::parseReal("5."), 5.0);
  EXPECT_EQ(de::parseReal("1e-310"), 1e-310);  // subnormal: representable, kept (std::stod threw)
  EXPECT_EQ(de::parseReal("-inf"), -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(*de::parseReal("nan")));
  for (const char* bad : {"", ".", "+", "e5", "1e", "1.5x", "2,5", " 1", "1 ", "+-1", "0x10", "1e400", "1e-400"})
    EXPECT_FALSE(de::parseReal(bad)) << "'" << bad << "'";
}
