// clothsim merge SHARD... [--csv FILE] [--summary FILE.json] [--plot FILE.png]
//
// Joins the parts of a sharded study (bench, stability, converge or golden check run with
// --shard K/N, each writing a directory F.shard-K-of-N/, study_shard.h) into what the study
// writes in one process: the CSV (the same header, the same rows in the same order), the
// --summary JSON (not converge's) and the figure, timing aside (it measures the machine each
// part ran on). Without --csv, a study's CSV goes to stdout (golden's stdout is its report: a
// line per image, the tally). Each study's own ending is a row of kStudyMerges.
//
// Refuses, with one line naming the file: a directory that is not a shard, and shards of
// different studies, scenes, options, versions or shard counts. Lists every missing and
// incomplete shard and exits 1 without writing anything.
//
// A merged bench ends as the single-process one does: a reference not converged against the
// smallest error keeps the CSV, draws no plot and exits 1. A merged golden check with an
// image that differs, is missing or diverged exits 1, naming the manifest entries.
//
// Exit codes: 0; 2 bad options or shards that do not belong together; 1 missing or
// incomplete shards, a bench reference not converged, a golden image failed, I/O, the plot.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>

#include "clip/studies/study_common.h"
#include "clip/merge/study_merge.h"
#include "clip/studies/study_shard.h"
#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/progress.h"
#include "clip/common/summary_json.h"
#include "clip/golden/golden_report.h"
#include "study/study.h"
#include "study/work_precision.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::cli {
namespace {

namespace fs = std::filesystem;

struct MergeOptions {
  std::vector<std::string> shards;
  std::string csv, plot, summary;
};

std::vector<ShardPart> complete_parts(const MergeOptions& o) {
  std::vector<ShardPart> parts;
  for (const std::string& dir : o.shards) parts.push_back(read_part(dir));
  check_same_study(parts);
  const std::string missing = missing_parts(parts);
  if (!missing.empty()) {
    std::fputs(missing.c_str(), stderr);
    throw RuntimeFailure("merge: the study is not complete (above); nothing written");
  }
  return parts;
}

// Every file merge reads: what the shards hold.
std::vector<PathRole> shard_files(const MergeOptions& o) {
  std::vector<PathRole> files;
  for (const std::string& dir : o.shards) {
    std::error_code ec;
    files.push_back({dir, "the shard"});
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
      if (it->is_regular_file(ec)) files.push_back({it->path().string(), "a file of the shard " + dir});
  }
  return files;
}

int merge_command(const MergeOptions& o) {
  refuse_clashing_paths(shard_files(o), {{o.csv, "--csv"}, {o.plot, "--plot"}, {o.summary, "--summary"}});
  if (!o.csv.empty()) require_writable_parent(o.csv, "--csv");
  if (!o.summary.empty()) require_writable_parent(o.summary, "--summary");
  const std::vector<ShardPart> parts = complete_parts(o);
  const StudyMerge& study = study_merge(parts.front());
  const analysis::Provenance& p = parts.front().provenance;
  if (!o.plot.empty() && !study.plot_script) throw UsageError("--plot: " + p.study + " draws no figure");
  if (!o.summary.empty() && !study.summary_keys)
    throw UsageError("--summary: a merged " + p.study + " writes its CSV and figure only; its summary's means are the CSV's");
  std::unique_ptr<PlotScript> plot;
  if (!o.plot.empty()) plot = std::make_unique<PlotScript>(study.plot_script, o.plot);
  MergedStudy merged{p, merged_csv(parts), o.summary.empty() ? std::vector<JsonObject>{} : merged_lanes(parts)};
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    std::fputs(merged.csv.c_str(), file.stream());
    file.commit();
  };
  if (!o.csv.empty()) write_to(o.csv);
  else if (study.csv_to_stdout) std::fputs(merged.csv.c_str(), stdout);
  if (!o.summary.empty()) write_summary(o.summary, p.study, p.scene, merged.lanes, study.summary_keys(merged));
  const bool quiet_stdout = o.csv.empty() && study.csv_to_stdout;
  std::fprintf(quiet_stdout ? stderr : stdout, "merge: %s of %s, %zu shards, %zu items%s%s\n", p.study.c_str(),
               p.scene.c_str(), parts.size(), p.total_items, o.csv.empty() ? "" : " -> ", o.csv.c_str());
  std::fflush(stdout);
  const std::string problem = study.conclusion ? study.conclusion(merged, o.csv) : "";
  if (!problem.empty()) throw RuntimeFailure(problem);
  if (plot) plot->draw_from_csv(o.csv, write_to, {"--title", p.title}, {o.csv, o.summary});
  return kOk;
}

}  // namespace

void add_merge_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* sub = app.add_subcommand(
      "merge", "Join the shards of a sharded bench, stability, converge or golden check (--shard K/N) into what one process writes");
  sub->add_option("shards", o->shards, "The shard directories (F.shard-K-of-N), all of one study")
      ->required()
      ->type_name("SHARD...");
  sub->add_option("--csv", o->csv, "Write the merged CSV here (default: stdout)")->type_name("FILE.csv");
  sub->add_option("--summary", o->summary, "Write the study's --summary JSON (docs/summary.md)")->type_name("FILE.json");
  sub->add_option("--plot", o->plot, "Draw the study's figure (needs python3-matplotlib)")->type_name("FILE.png");
  add_no_overwrite_option(sub);
  sub->callback([o, &command] { command = [o] { return merge_command(*o); }; });
}

}  // namespace clothsim::cli
