// --progress auto|always|never and --quiet: a bar on a terminal, plain lines for a log when
// asked (at the start, about every period, at the end), nothing otherwise.
#include "clip/common/progress.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

using clip::Progress;
using clip::ProgressMode;
using namespace std::chrono_literals;

// What a Progress wrote when driven through `done` = 1..total, `pause` apart.
std::string written(ProgressMode mode, bool quiet, bool terminal, int total, std::chrono::milliseconds pause,
                    std::chrono::milliseconds period) {
  std::FILE* f = std::tmpfile();
  {
    Progress p("run drape", total, "frames", mode, quiet, terminal, f, period);
    for (int k = 1; k <= total; ++k) {
      std::this_thread::sleep_for(pause);
      p.update(k);
    }
  }
  std::rewind(f);
  std::string text;
  for (int c; (c = std::fgetc(f)) != EOF;) text += static_cast<char>(c);
  std::fclose(f);
  return text;
}

TEST(Progress, AlwaysWritesPlainLinesToALogAtTheStartEveryPeriodAndTheEnd) {
  const std::string log = written(ProgressMode::always, false, false, 10, 30ms, 100ms);
  EXPECT_EQ(log.find('\r'), std::string::npos) << log;  // no terminal control in a log
  EXPECT_EQ(log.rfind("run drape: 0/10 frames\n", 0), 0u) << log;
  EXPECT_NE(log.find("run drape: 10/10 frames, done in "), std::string::npos) << log;
  // 300 ms of work, a line per 100 ms: the start, two or three in between, the end.
  const int lines = line_count(log);
  EXPECT_GE(lines, 4) << log;
  EXPECT_LE(lines, 6) << log;
  EXPECT_NE(log.find(" s elapsed, "), std::string::npos) << log;
}

TEST(Progress, AutoWritesNothingToALogAndABarToATerminal) {
  EXPECT_EQ(written(ProgressMode::automatic, false, false, 5, 0ms, 100ms), "");
  const std::string bar = written(ProgressMode::automatic, false, true, 5, 0ms, 100ms);
  EXPECT_EQ(bar.rfind("\r\033[Krun drape  1/5 frames", 0), 0u) << bar;
  EXPECT_EQ(bar.substr(bar.size() - 4), "\r\033[K");  // cleared at the end
}

TEST(Progress, NeverAndQuietWriteNothingEvenToATerminal) {
  EXPECT_EQ(written(ProgressMode::never, false, true, 5, 0ms, 100ms), "");
  EXPECT_EQ(written(ProgressMode::always, true, true, 5, 0ms, 100ms), "");
  EXPECT_EQ(written(ProgressMode::always, true, false, 5, 0ms, 100ms), "");
}

TEST(Progress, TheTimeLeftScalesTheTimeSoFarByTheShareOfTheWorkDone) {
  // One run of 11 done, but it was 60 % of the work: 10 s so far leaves 6.7 s, not 100 s.
  EXPECT_NEAR(Progress::seconds_left(10.0, 0.6), 10.0 * 0.4 / 0.6, 1e-12);
  EXPECT_DOUBLE_EQ(Progress::seconds_left(10.0, 1.0), 0.0);
  EXPECT_TRUE(std::isnan(Progress::seconds_left(10.0, 0.0))) << "nothing done: no estimate";
  // A log line with the share: "1/11 runs, ... s elapsed, ... s left" from the share, not the count.
  std::FILE* f = std::tmpfile();
  {
    Progress p("bench sheet", 11, "runs", ProgressMode::always, false, false, f, 0ms);
    std::this_thread::sleep_for(300ms);
    p.update(1, 0.6);
  }
  std::rewind(f);
  char line[256] = {};
  ASSERT_TRUE(std::fgets(line, sizeof line, f));  // the start
  ASSERT_TRUE(std::fgets(line, sizeof line, f));
  std::fclose(f);
  double elapsed = 0.0, left = 0.0;
  ASSERT_EQ(std::sscanf(line, "bench sheet: 1/11 runs, %lf s elapsed, %lf s left", &elapsed, &left), 2) << line;
  EXPECT_NEAR(left, elapsed * 0.4 / 0.6, 0.1) << line;  // (both printed to 0.1 s)
  EXPECT_LT(left, elapsed) << "by count it would be 10 x the time so far";
}

TEST(Progress, RunWithProgressAlwaysLogsLinesWhenStderrIsAFile) {
  const CliResult r = run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml", "--duration", "1",
                                    "--progress", "always"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.rfind("run spring: 0/31 frames\n", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("run spring: 31/31 frames, done in "), std::string::npos) << r.err;
  const CliResult quiet = run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml", "--duration", "1",
                                        "--progress", "always", "--quiet"});
  EXPECT_EQ(quiet.err, "");
  EXPECT_NE(quiet.out, "");  // the results stay
  const CliResult bad = run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml", "--progress", "sometimes"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--progress"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace clothsim::testing
