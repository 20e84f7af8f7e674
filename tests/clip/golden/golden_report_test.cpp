// golden check's verdicts: the CSV row reads back to the same verdict (merge rebuilds the
// report from the rows shards journaled), and the report line says what one check says.
#include "clip/golden/golden_report.h"

#include <gtest/gtest.h>

namespace clothsim::clip {
namespace {

GoldenVerdict differs() {
  GoldenVerdict v;
  v.entry = 2;
  v.image = "drape, rk4_t100ms.png";  // a comma: the row quotes it
  v.t = 0.1;
  v.rms = 29.883;
  v.max = 204;
  v.over_fraction = 0.34903;
  v.threshold = 16;
  v.problem = "rms 29.883 (tolerance 2), max 204";
  v.actual = "out/a \"b\".actual.png";
  v.diff = "out/a.diff.png";
  return v;
}

TEST(GoldenReport, ARowReadsBackToTheSameVerdictAndLine) {
  GoldenVerdict missing;
  missing.entry = 0;
  missing.image = "spring_t500ms.png";
  missing.t = 0.5;
  missing.threshold = 16;
  missing.problem = "missing (`clothsim golden update` writes it)";
  missing.actual = "spring_t500ms.actual.png";
  GoldenVerdict ok = differs();
  ok.ok = true;
  ok.problem = ok.actual = ok.diff = "";
  for (const GoldenVerdict& v : {differs(), missing, ok}) {
    std::string row = golden_csv_row(v);
    ASSERT_EQ(row.back(), '\n');
    row.pop_back();
    const GoldenVerdict back = parse_golden_row(row);
    EXPECT_EQ(golden_report_line(back), golden_report_line(v));
    EXPECT_EQ(golden_csv_row(back), golden_csv_row(v));
    EXPECT_EQ(back.entry, v.entry);
    EXPECT_EQ(back.t, v.t);
  }
  EXPECT_EQ(golden_report_line(missing),
            "FAIL  spring_t500ms.png  missing (`clothsim golden update` writes it); actual: spring_t500ms.actual.png");
  EXPECT_EQ(golden_report_line(ok), "ok    drape, rk4_t100ms.png  rms 29.883, max 204, 34.903% past 16");
}

TEST(GoldenReport, TheTallyAndTheFailuresNameTheEntries) {
  GoldenVerdict ok = differs();
  ok.ok = true;
  const std::vector<GoldenVerdict> verdicts{ok, differs()};
  EXPECT_EQ(golden_tally(verdicts, "m.yaml"), "golden: 1 of 2 images match (m.yaml)");
  EXPECT_EQ(golden_failures(verdicts), "goldens[2] (drape, rk4_t100ms.png)");
  EXPECT_EQ(golden_failures({ok}), "");
}

TEST(GoldenReport, ARowOfAnotherStudyIsRefused) {
  EXPECT_THROW(parse_golden_row("symplectic_euler,0.01,100"), std::runtime_error);
  EXPECT_THROW(parse_golden_row("0,a.png,0.1,maybe,,,,16,,,"), std::runtime_error);
}

}  // namespace
}  // namespace clothsim::clip
