// The progress line of long runs: its text, drawn only when enabled (stderr a terminal), cleared
// at the end.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "sweep/progress.hpp"

namespace mechgen {
namespace {

std::string contents(std::FILE* file) {
  std::rewind(file);
  std::string text;
  for (int c; (c = std::fgetc(file)) != EOF;) text += static_cast<char>(c);
  return text;
}

TEST(Progress, LineGivesDoneRateAndTimeLeft) {
  // 250 of 1000 samples in 0.5 s: 500 samples/s, 750 left take 1.5 s.
  EXPECT_EQ(progress_line("sweep jansen", 250, 1000, 0.5),
            "sweep jansen: 250 / 1000 samples (25%), 5e+02 samples/s, 1.5 s left");
  EXPECT_EQ(progress_line("grid x", 0, 10, 0.0),
            "grid x: 0 / 10 samples (0%), 0 samples/s, estimating");
}

TEST(Progress, DrawsWhenEnabledAndClearsAtTheEnd) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    Progress progress("sweep m", 10, file, true);
    progress.advance(2);  // the first samples start the clock
    progress.advance(2);  // within the first 0.3 s: not drawn
    EXPECT_EQ(contents(file), "");
    std::this_thread::sleep_for(std::chrono::milliseconds(350));
    progress.advance(6);  // drawn
  }
  const std::string text = contents(file);
  EXPECT_EQ(text.rfind("\rsweep m: 10 / 10 samples (100%), ", 0), 0u) << text;
  // The destructor overwrites the line with spaces and returns to its start.
  const size_t width = text.find('\r', 1) - 1;
  EXPECT_EQ(text.substr(width + 1), "\r" + std::string(width, ' ') + "\r");
  std::fclose(file);
}

TEST(Progress, ShortRunDrawsNothing) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    Progress progress("sweep m", 3, file, true);
    for (int i = 0; i < 3; ++i) progress.advance(1);
  }
  EXPECT_EQ(contents(file), "");
  std::fclose(file);
}

TEST(Progress, SilentWhenDisabled) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    Progress progress("sweep m", 3, file, false);
    progress.advance(3);
  }
  EXPECT_EQ(contents(file), "");
  std::fclose(file);
}

}  // namespace
}  // namespace mechgen
