// What bench and stability share (src/clip/studies/study_common.h): here the line they end on when
// stopped, which must name every file that stays on disk.
#include "clip/studies/study_common.h"

#include <gtest/gtest.h>

namespace clothsim::clip {
namespace {

// (No signal has arrived in this process: the line then says "a signal"; a command's names it,
// as Signals.* in cli_common_test check.)
TEST(StudyInterruptedMessage, NamesEveryFileThatStaysAsIncompleteAndThePlotNotDrawn) {
  EXPECT_EQ(study_interrupted_message(3, 28, "runs", {"wp.csv", "wp.json"}, "wp.png"),
            "stopped by a signal: 3 of 28 runs finished; kept wp.csv (incomplete), wp.json (incomplete); not written: wp.png");
  EXPECT_EQ(study_interrupted_message(0, 20, "searches", {"", "st.json"}, ""),
            "stopped by a signal: 0 of 20 searches finished; kept st.json (incomplete)")
      << "an output not asked for is not named";
  EXPECT_EQ(study_interrupted_message(2, 5, "runs", {"", ""}, "wp.png"),
            "stopped by a signal: 2 of 5 runs finished; nothing kept; not written: wp.png");
}

TEST(StudyInterruptedMessage, FilesWrittenAfterEveryRunFinishedAreNotCalledIncomplete) {
  // The signal came after the last run: the files hold every run, only the plot is missing.
  EXPECT_EQ(study_interrupted_message(28, 28, "runs", {"wp.csv", "wp.json"}, "wp.png"),
            "stopped by a signal: 28 of 28 runs finished; kept wp.csv, wp.json; not written: wp.png");
}

}  // namespace
}  // namespace clothsim::clip

namespace clothsim::clip {
namespace {

TEST(CsvText, QuotesWhatWouldBreakARowAndBlanksControlBytes) {
  EXPECT_EQ(csv_text("drape"), "drape");
  EXPECT_EQ(csv_text("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_text("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_text("a\r\nb"), "\"a  b\"");
  EXPECT_EQ(csv_text("\x1b[2J"), "\" [2J\"");
  EXPECT_EQ(csv_text(std::string("a\0b", 3)), "\"a b\"") << "a NUL cuts nothing";
}

}  // namespace
}  // namespace clothsim::clip
