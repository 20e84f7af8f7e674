// What `clothsim merge` does with the parts of a sharded study (study_shard.h): reads each
// part's record and rows, checks they belong to one study and cover it, joins the rows into
// the CSV one process writes, and ends each study as it ends (kStudyMerges: bench's reference
// check, golden's report, the summary's keys). tools/cli/studies/cmd_merge.cpp parses,
// prints and exits.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "clip/common/summary_json.h"
#include "study/shard.h"

namespace clothsim::clip {

struct ShardPart {
  std::string dir;
  analysis::Provenance provenance;
  std::map<std::size_t, std::string> rows;  // finished items' rows, by item
};

// A part's record and finished rows; UsageError naming the file for a directory that is no shard.
ShardPart read_part(const std::string& dir);

// Every part must be a part of the first one's study.
void check_same_study(const std::vector<ShardPart>& parts);

// Missing and incomplete parts, one line each; empty when every item is in.
std::string missing_parts(const std::vector<ShardPart>& parts);

// Header and rows in item order: what the study writes in one process.
std::string merged_csv(const std::vector<ShardPart>& parts);

// One part's header and finished rows in item order: what its process has written so far (the
// Python module's DataFrame of a shard).
std::string part_csv(const ShardPart& part);

// bench's last check, which needs every error (work_precision.h): the reference's own
// change at most reference_margin x the smallest RMS error. "" when it holds.
std::string bench_reference_problem(const std::string& csv, double round_off);

// The merged study: the first part's record, the CSV one process writes, and (for --summary)
// each item's lane as the shard dumped it, in item order.
struct MergedStudy {
  const analysis::Provenance& provenance;
  std::string csv;
  std::vector<JsonObject> lanes;
};

// What merge does for each study beyond joining its rows.
struct StudyMerge {
  const char* study;
  const char* plot_script;  // nullptr: the study draws no figure
  bool csv_to_stdout;       // without --csv (golden's stdout is its report)
  JsonObject (*summary_keys)(const MergedStudy&);  // the summary's own keys; nullptr: no --summary
  // Prints what the study prints at its end; says why it fails ("" when it does not).
  std::string (*conclusion)(const MergedStudy&, const std::string& csv_path);
};

// Every item's summary lane, in item order.
std::vector<JsonObject> merged_lanes(const std::vector<ShardPart>& parts);

// The row of kStudyMerges for the part's study; UsageError for a study merge does not know.
const StudyMerge& study_merge(const ShardPart& part);

}  // namespace clothsim::clip
