// Progress lines for long start-up work (Utilities/ProgressLog.h; issue 16: sampling a 1 M-triangle
// body printed nothing for hours): quiet for the first interval, then at most one line per
// interval with the share done, and a closing line only when a progress line was written.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "Utilities/ProgressLog.h"

using namespace consph;

TEST(ProgressLog, QuietAtFirstThenOneLinePerIntervalAndADoneLine) {
  std::vector<std::string> lines;
  const LogSink sink = [&](LogLevel, const std::string& text) { lines.push_back(text); };
  ProgressLog progress(sink, "sampling body.obj (1000 triangles)", 1000, 0.5);
  progress.report(100);
  EXPECT_TRUE(lines.empty()) << "within the first interval";
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  progress.report(500);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].rfind("sampling body.obj (1000 triangles): 50 % after ", 0), 0u) << lines[0];
  progress.report(600);  // the same interval: no second line
  EXPECT_EQ(lines.size(), 1u);
  progress.finish();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[1].find(": done in "), std::string::npos) << lines[1];

  // Work done within the first interval says nothing at all.
  std::vector<std::string> quiet;
  ProgressLog fast([&](LogLevel, const std::string& text) { quiet.push_back(text); }, "fast", 10, 0.5);
  fast.report(10);
  fast.finish();
  EXPECT_TRUE(quiet.empty());
}
