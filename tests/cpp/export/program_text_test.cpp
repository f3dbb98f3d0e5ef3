// Tests of export/program_text.hpp: number formatting, line endings, job splitting, names.
#include "curvedslicer/export/program_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

TEST(ProgramText, FormatsFixedDecimalsWithoutNegativeZero) {
  EXPECT_EQ(formatFixed(1.0, 3), "1.000");
  EXPECT_EQ(formatFixed(-2.5, 1), "-2.5");
  EXPECT_EQ(formatFixed(123.45678, 2), "123.46");
  EXPECT_EQ(formatFixed(-0.0004, 3), "0.000");
  EXPECT_EQ(formatFixed(-0.0, 0), "0");
  EXPECT_EQ(formatFixed(-0.0006, 3), "-0.001");
  EXPECT_EQ(formatFixed(1e6, 1), "1000000.0");
  std::string s = "x=";
  appendFixed(s, 0.125, 4);
  appendInt(s, -42);
  EXPECT_EQ(s, "x=0.1250-42");
}

TEST(ProgramText, RejectsNonFiniteNumbers) {
  EXPECT_THROW(formatFixed(std::numeric_limits<double>::quiet_NaN(), 3), InvalidInput);
  EXPECT_THROW(formatFixed(std::numeric_limits<double>::infinity(), 3), InvalidInput);
  EXPECT_THROW(formatFixed(1.0, 18), InvalidInput);
}

TEST(ProgramText, UsesTheChosenLineEndingAndCountsLines) {
  ProgramText crlf(LineEnding::Crlf);
  crlf.line("NOP");
  crlf.buffer() += "END";
  crlf.endLine();
  EXPECT_EQ(crlf.str(), "NOP\r\nEND\r\n");
  EXPECT_EQ(crlf.lineCount(), 2u);
  ProgramText lf;
  lf.line("a");
  EXPECT_EQ(lf.take(), "a\n");
  EXPECT_EQ(lf.lineCount(), 0u);
}

TEST(ProgramText, SplitsAtPreferredBreaksWithinTheLimit) {
  // Three "paths" of 3, 4 and 2 items, cost 1 each; limit 5: cuts before path 2 and path 3.
  const std::vector<std::size_t> costs(9, 1);
  std::vector<bool> breaks(9, false);
  breaks[3] = breaks[7] = true;
  const auto chunks = splitAtLimit(costs, breaks, 5);
  ASSERT_EQ(chunks.size(), 3u);
  EXPECT_EQ(chunks[0].begin, 0u);
  EXPECT_EQ(chunks[0].end, 3u);
  EXPECT_EQ(chunks[1].end, 7u);
  EXPECT_EQ(chunks[2].end, 9u);
}

TEST(ProgramText, CutsInsideARunLongerThanTheLimit) {
  const std::vector<std::size_t> costs(12, 1);
  std::vector<bool> breaks(12, false);
  breaks[2] = true;  // a run of 10 items follows
  const auto chunks = splitAtLimit(costs, breaks, 4);
  // [0,2) at the preferred cut, then the long run in pieces of 4.
  ASSERT_EQ(chunks.size(), 4u);
  EXPECT_EQ(chunks[0].end, 2u);
  EXPECT_EQ(chunks[1].end, 6u);
  EXPECT_EQ(chunks[2].end, 10u);
  EXPECT_EQ(chunks[3].end, 12u);
  std::size_t covered = 0;
  for (const auto& c : chunks) {
    EXPECT_LE(c.size(), 4u);
    EXPECT_EQ(c.begin, covered);
    covered = c.end;
  }
  EXPECT_EQ(covered, costs.size());
}

TEST(ProgramText, RejectsAnItemLargerThanTheLimit) {
  EXPECT_THROW(splitAtLimit({1, 6, 1}, {false, false, false}, 5), InvalidInput);
  EXPECT_THROW(splitAtLimit({1, 1}, {false}, 5), InvalidInput);
  EXPECT_TRUE(splitAtLimit({}, {}, 5).empty());
}

TEST(ProgramText, MakesControllerNames) {
  EXPECT_EQ(makeProgramName("turbine base-1", 32, true), "TURBINE_BASE_1");
  EXPECT_EQ(makeProgramName("turbine base", 8, true), "TURBINE_");
  EXPECT_EQ(makeProgramName("1st", 8, false), "P1st");
  EXPECT_EQ(makeProgramName("", 8, true), "P");
  EXPECT_THROW(makeProgramName("a", 0, true), InvalidInput);
  EXPECT_EQ(makeSubJobName("WAAMPART", 3, 12, 8), "WAAMPA03");
  EXPECT_EQ(makeSubJobName("W", 7, 9, 32), "W7");
  EXPECT_THROW(makeSubJobName("W", 1, 1000, 3), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
