// The CLI's progress lines off a terminal: one per 10 % of the end time, and one whenever a minute
// of wall time has passed without a line, on a clock the test moves (no sleeping).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "progress.hpp"

namespace spall::cli {
namespace {

// Progress lines written to a temporary file, with a clock that stands still until moved.
class ProgressLines {
 public:
  ProgressLines() : file_(std::tmpfile()) {}
  ~ProgressLines() { std::fclose(file_); }

  Progress::Environment environment() {
    Progress::Environment environment;
    environment.now = [this] { return now_; };
    environment.out = file_;
    environment.terminal = false;
    return environment;
  }
  void advance(Progress::Clock::duration elapsed) { now_ += elapsed; }
  std::FILE* file() const { return file_; }
  int count() const {
    std::rewind(file_);
    int lines = 0;
    for (int c = std::fgetc(file_); c != EOF; c = std::fgetc(file_)) lines += c == '\n';
    return lines;
  }

 private:
  std::FILE* file_;
  Progress::Clock::time_point now_{};
};

solver::StepInfo at(double time, long long step) { return {step, time, 1e-3}; }

TEST(progress, OffATerminalALinePerTenthOfTheRun) {
  ProgressLines lines;
  Progress progress(1.0, 100, lines.environment());
  for (int step = 1; step <= 1000; ++step) progress.update(at(step * 1e-3, step));
  progress.finish(at(1.0, 1000));
  EXPECT_EQ(lines.count(), 10);
}

TEST(progress, OffATerminalALineAtLeastEveryMinute) {
  ProgressLines lines;
  Progress progress(1.0, 100, lines.environment());
  // 5 % of the run in 10 minutes: no tenth is reached, but every minute gets its line.
  for (int step = 1; step <= 50; ++step) {
    lines.advance(std::chrono::seconds(12));
    progress.update(at(step * 1e-3, step));
  }
  EXPECT_EQ(lines.count(), 10);
  // A tenth reached just after a line prints at once; the minute then counts from that line.
  lines.advance(std::chrono::seconds(1));
  progress.update(at(0.1, 51));
  EXPECT_EQ(lines.count(), 11);
  lines.advance(std::chrono::seconds(59));
  progress.update(at(0.11, 52));
  EXPECT_EQ(lines.count(), 11);
  lines.advance(std::chrono::seconds(1));
  progress.update(at(0.12, 53));
  EXPECT_EQ(lines.count(), 12);
  EXPECT_DOUBLE_EQ(progress.elapsed_seconds(), 50 * 12 + 61);
}

TEST(progress, ARestartedRunCountsItsOwnStepsAndTime) {
  // Continued at step 600, t = 0.6 (of 1.0); then 100 steps to t = 0.7 in 10 s: 100 nodes x 100
  // steps / 10 s = 1000 node-steps/s, and 0.3 left at 0.1 per 10 s: ETA 30 s. The 70 % line is the
  // first one this process prints (60 % was passed before the restart).
  ProgressLines lines;
  Progress progress(1.0, 100, lines.environment());
  progress.continue_from(at(0.6, 600));
  for (int step = 601; step <= 700; ++step) {
    lines.advance(std::chrono::milliseconds(100));
    progress.update(at(step * 1e-3, step));
  }
  EXPECT_EQ(lines.count(), 1);
  EXPECT_EQ(progress.steps_taken(at(0.7, 700)), 100);
  std::rewind(lines.file());
  char text[256] = {};
  ASSERT_NE(std::fgets(text, sizeof text, lines.file()), nullptr);
  EXPECT_NE(std::string(text).find("1.000e+03 node-steps/s  ETA 30 s"), std::string::npos) << text;
}

}  // namespace
}  // namespace spall::cli
