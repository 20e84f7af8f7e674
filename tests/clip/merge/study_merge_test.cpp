// merge's work (src/clip/merge/study_merge.h): the parts of one study joined into the CSV one
// process writes, a gap or a stranger refused, and bench's reference judged on every error.
#include "clip/merge/study_merge.h"

#include <gtest/gtest.h>

#include "clip/common/cli_common.h"

namespace clothsim::clip {
namespace {

// Shard k of n of a study of `total` items, holding rows for `items` ("row<item>\n").
ShardPart part(int k, int n, std::size_t total, const std::vector<std::size_t>& items) {
  ShardPart p;
  p.dir = "wp.csv.shard-" + std::to_string(k) + "-of-" + std::to_string(n);
  p.provenance.study = "bench";
  p.provenance.version = "1";
  p.provenance.header = "a,b";
  p.provenance.shard = {k, n};
  p.provenance.total_items = total;
  p.provenance.items = items;
  for (std::size_t i : items) p.rows[i] = "row" + std::to_string(i) + "\n";
  return p;
}

TEST(MergedCsv, JoinsThePartsRowsInItemOrderUnderOneHeader) {
  const std::vector<ShardPart> parts{part(1, 2, 4, {1, 3}), part(2, 2, 4, {0, 2})};
  EXPECT_EQ(merged_csv(parts), "a,b\nrow0\nrow1\nrow2\nrow3\n");
}

TEST(PartCsv, IsOnePartsFinishedRowsInItemOrderWhateverTheRestHolds) {
  EXPECT_EQ(part_csv(part(2, 2, 4, {2, 0})), "a,b\nrow0\nrow2\n");
}

TEST(MergedCsv, RefusesPartsThatDoNotCoverTheStudyOnce) {
  EXPECT_THROW(merged_csv({part(1, 2, 4, {0, 1}), part(2, 2, 4, {3})}), UsageError) << "item 2 is nobody's";
}

TEST(MissingParts, NamesAMissingShardBesideTheOthersAndAnIncompleteOne) {
  ShardPart half = part(1, 3, 6, {0, 1});
  half.rows.erase(1);  // the shard stopped after its first item
  const std::string said = missing_parts({half, part(3, 3, 6, {4, 5})});
  EXPECT_NE(said.find("missing: shard 2/3 (wp.csv.shard-2-of-3)"), std::string::npos) << said;
  EXPECT_NE(said.find("incomplete: wp.csv.shard-1-of-3 (1 of 2 items"), std::string::npos) << said;
  EXPECT_EQ(missing_parts({part(1, 1, 2, {0, 1})}), "");
}

TEST(CheckSameStudy, RefusesAShardOfAnotherStudyAndTheSameShardTwice) {
  ShardPart other = part(2, 2, 4, {0, 2});
  other.provenance.study = "stability";
  EXPECT_THROW(check_same_study({part(1, 2, 4, {1, 3}), other}), UsageError);
  EXPECT_THROW(check_same_study({part(1, 2, 4, {1, 3}), part(1, 2, 4, {1, 3})}), UsageError);
  EXPECT_NO_THROW(check_same_study({part(1, 2, 4, {1, 3}), part(2, 2, 4, {0, 2})}));
}

TEST(BenchReferenceProblem, FailsAReferenceLessThanTenTimesBetterThanAnUnresolvedRun) {
  const std::string resolved = "reference_change,unresolved\n1e-9,0\n1e-9,0\n";
  EXPECT_EQ(bench_reference_problem(resolved, 1e-15), "");
  const std::string unresolved = "reference_change,unresolved\n1e-6,1\n1e-6,0\n";
  EXPECT_NE(bench_reference_problem(unresolved, 1e-15).find("not converged"), std::string::npos);
  EXPECT_EQ(bench_reference_problem(unresolved, 1e-5), "") << "at round-off, as the reference is";
}

TEST(StudyMerge, HasARowForEveryShardedStudyAndRefusesOthers) {
  ShardPart p = part(1, 1, 1, {0});
  for (const char* study : {"bench", "stability", "converge", "golden"}) {
    p.provenance.study = study;
    EXPECT_STREQ(study_merge(p).study, study);
  }
  p.provenance.study = "compare";
  EXPECT_THROW(study_merge(p), UsageError);
}

}  // namespace
}  // namespace clothsim::clip
