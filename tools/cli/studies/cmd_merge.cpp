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
#include "clip/studies/study_shard.h"
#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
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

struct ShardPart {
  std::string dir;
  analysis::Provenance provenance;
  std::map<std::size_t, std::string> rows;  // finished items' rows, by item
};

ShardPart read_part(const std::string& dir) {
  ShardPart part{dir, {}, {}};
  const std::string record = dir + "/provenance";
  std::string text;
  try {
    text = analysis::read_whole_file(record);
  } catch (const std::runtime_error&) {
    throw UsageError(dir + ": not a shard (no " + record + "; a shard is the F.shard-K-of-N/ a --shard run writes)");
  }
  try {
    part.provenance = analysis::parse_provenance(text);
    part.rows = analysis::Journal::read_items(dir);
  } catch (const analysis::StudyError& e) {
    throw UsageError(record + ": " + e.what());
  } catch (const std::runtime_error& e) {
    throw RuntimeFailure(e.what());
  }
  return part;
}

// Every part must be a part of the first one's study.
void check_same_study(const std::vector<ShardPart>& parts) {
  const ShardPart& first = parts.front();
  std::map<int, std::string> seen;
  for (const ShardPart& p : parts) {
    const std::string field = analysis::provenance_mismatch(first.provenance, p.provenance);
    if (!field.empty()) {
      const std::map<std::string, std::string> what{
          {"study", "study"}, {"version", "clothsim version"}, {"scene_hash", "scene (or --set)"},
          {"plan_hash", "study options"}, {"header", "CSV columns"}, {"shard count", "shard count"}};
      throw UsageError(p.dir + ": a shard of a different " + what.at(field) + " than " + first.dir + " (" +
                       p.provenance.study + " " + analysis::shard_text(p.provenance.shard) + " of " +
                       p.provenance.scene + ")");
    }
    const auto [at, fresh] = seen.emplace(p.provenance.shard.index, p.dir);
    if (!fresh) throw UsageError(p.dir + ": shard " + analysis::shard_text(p.provenance.shard) + " is also " + at->second);
  }
}

// "out.csv.shard-3-of-4" beside a given part's name, for the list of missing parts.
std::string sibling_name(const ShardPart& part, int index) {
  std::string dir = part.dir;
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  const std::string mine = ".shard-" + std::to_string(part.provenance.shard.index) + "-of-";
  const std::size_t at = dir.rfind(mine);
  if (at == std::string::npos) return "";
  return dir.substr(0, at) + ".shard-" + std::to_string(index) + "-of-" + std::to_string(part.provenance.shard.count);
}

// Missing and incomplete parts, one line each; empty when every item is in.
std::string missing_parts(const std::vector<ShardPart>& parts) {
  std::string out;
  const int count = parts.front().provenance.shard.count;
  std::map<int, const ShardPart*> by_index;
  for (const ShardPart& p : parts) by_index[p.provenance.shard.index] = &p;
  for (int k = 1; k <= count; ++k) {
    const auto it = by_index.find(k);
    if (it == by_index.end()) {
      const std::string name = sibling_name(parts.front(), k);
      out += "  missing: shard " + std::to_string(k) + "/" + std::to_string(count) +
             (name.empty() ? "" : " (" + name + ")") + "\n";
      continue;
    }
    const ShardPart& p = *it->second;
    std::size_t finished = 0;
    for (std::size_t item : p.provenance.items) finished += p.rows.count(item);
    if (finished < p.provenance.items.size())
      out += "  incomplete: " + p.dir + " (" + std::to_string(finished) + " of " +
             std::to_string(p.provenance.items.size()) + " items; rerun its command)\n";
  }
  return out;
}

// Header and rows in item order: what the study writes in one process.
std::string merged_csv(const std::vector<ShardPart>& parts) {
  std::map<std::size_t, const std::string*> rows;
  for (const ShardPart& p : parts)
    for (std::size_t item : p.provenance.items) rows[item] = &p.rows.at(item);
  const std::size_t total = parts.front().provenance.total_items;
  if (rows.size() != total || (total > 0 && rows.rbegin()->first != total - 1))
    throw UsageError(parts.front().dir + ": the shards' items do not cover the study's " + std::to_string(total) +
                     " once each (shards of different splits?)");
  std::string csv = parts.front().provenance.header + "\n";
  for (const auto& [item, row] : rows) csv += *row;
  return csv;
}

// bench's last check, which needs every error (work_precision.h): the reference's own
// change at most reference_margin x the smallest RMS error. "" when it holds.
std::string bench_reference_problem(const std::string& csv, double round_off) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_cells(line);
  const auto column = [&](const char* name) { return std::find(header.begin(), header.end(), name) - header.begin(); };
  const std::size_t change_at = column("reference_change"), unresolved_at = column("unresolved");
  double change = NAN;
  int unresolved = 0;  // as work_precision judges: runs under 10x its error, unless it is at round-off
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = csv_cells(line);
    if (cells.size() != header.size()) continue;
    if (unresolved_at < cells.size() && cells[unresolved_at] == "1") ++unresolved;
    change = std::strtod(cells[change_at].c_str(), nullptr);
  }
  const double margin = analysis::WorkPrecisionSpec{}.reference_margin;
  char why[300] = "";
  if (std::isnan(change))
    std::snprintf(why, sizeof why, "the reference runs did not both reach T (see a shard's log)");
  else if (unresolved > 0 && change > round_off)
    std::snprintf(why, sizeof why, "the reference is not converged: its estimated error (%.3g m RMS) is more than %g x "
                  "the error of %d run%s (unresolved)", change, margin, unresolved, unresolved == 1 ? "" : "s");
  return why;
}

// The merged study: the first part's record, the CSV one process writes, and (for --summary)
// each item's lane as the shard dumped it, in item order.
struct MergedStudy {
  const analysis::Provenance& provenance;
  std::string csv;
  std::vector<JsonObject> lanes;
};

// The first row's cells by column: the settings every row of a study repeats.
std::map<std::string, std::string> first_row(const std::string& csv) {
  std::istringstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  const std::vector<std::string> names = csv_cells(header), cells = csv_cells(row);
  std::map<std::string, std::string> by_name;
  for (std::size_t i = 0; i < names.size() && i < cells.size(); ++i) by_name[names[i]] = cells[i];
  return by_name;
}

double number(const std::string& cell) { return cell.empty() ? NAN : std::strtod(cell.c_str(), nullptr); }

JsonObject stability_keys(const MergedStudy& m) {
  std::map<std::string, std::string> row = first_row(m.csv);
  JsonObject keys;
  keys.text("param", row["param"])
      .number("duration", number(row["duration"]))
      .number("min_dt", number(row["min_dt"]))
      .number("max_dt", number(row["max_dt"]))
      .boolean("complete", true);
  return keys;
}

// The round-off floor of the shards' scene (work_precision.h), from its file; a file gone
// since the shards ran leaves the floor of a scene of 1 m.
double merged_round_off(const analysis::Provenance& p) {
  try {
    return analysis::round_off_floor(build_model(load_scene(p.scene, {}, false)));
  } catch (const std::exception&) {
    return analysis::kRoundOffRelative;
  }
}

JsonObject bench_keys(const MergedStudy& m) {
  std::map<std::string, std::string> row = first_row(m.csv);
  const bool adaptive = number(row["reference_dt"]) == 0.0;  // (the adaptive reference has no step)
  return bench_summary_keys(number(row["duration"]), true,
                            adaptive ? "dopri5 (adaptive)" : std::string(integrator_name(analysis::WorkPrecisionSpec{}.reference_integrator)),
                            number(row["reference_dt"]), number(row["reference_change"]),
                            bench_reference_problem(m.csv, merged_round_off(m.provenance)).empty());
}

// As the single-process bench ends: a reference not converged fails it, CSV kept, no plot.
std::string bench_conclusion(const MergedStudy& m, const std::string& csv_path) {
  const std::string why = bench_reference_problem(m.csv, merged_round_off(m.provenance));
  if (why.empty()) return "";
  return m.provenance.scene + ": " + why + (csv_path.empty() ? "" : " (kept for inspection: " + csv_path + ")") +
         "; no plot drawn";
}

std::vector<GoldenVerdict> golden_verdicts(const std::string& csv) {
  std::vector<GoldenVerdict> verdicts;
  std::istringstream in(after_first_line(csv));
  for (std::string row; std::getline(in, row);) verdicts.push_back(parse_golden_row(row));
  return verdicts;
}

JsonObject golden_keys(const MergedStudy& m) { return golden_summary_keys(golden_verdicts(m.csv)); }

// What one golden check prints (a line per image, the tally); a failed image fails the merge.
std::string golden_conclusion(const MergedStudy& m, const std::string&) {
  const std::vector<GoldenVerdict> verdicts = golden_verdicts(m.csv);
  for (const GoldenVerdict& v : verdicts) std::printf("%s\n", golden_report_line(v).c_str());
  std::printf("%s\n", golden_tally(verdicts, m.provenance.scene).c_str());
  const std::string failed = golden_failures(verdicts);
  return failed.empty() ? "" : "golden check of " + m.provenance.scene + " failed: " + failed;
}

// What merge does for each study beyond joining its rows.
struct StudyMerge {
  const char* study;
  const char* plot_script;  // nullptr: the study draws no figure
  bool csv_to_stdout;       // without --csv (golden's stdout is its report)
  JsonObject (*summary_keys)(const MergedStudy&);  // the summary's own keys; nullptr: no --summary
  // Prints what the study prints at its end; says why it fails ("" when it does not).
  std::string (*conclusion)(const MergedStudy&, const std::string& csv_path);
};

const StudyMerge kStudyMerges[] = {
    {"stability", "plot_stability.py", true, stability_keys, nullptr},
    {"bench", "plot_work_precision.py", true, bench_keys, bench_conclusion},
    {"golden", nullptr, false, golden_keys, golden_conclusion},
    {"converge", "plot_convergence.py", true, nullptr, nullptr},
};

const StudyMerge& study_merge(const ShardPart& part) {
  for (const StudyMerge& m : kStudyMerges)
    if (part.provenance.study == m.study) return m;
  throw UsageError(part.dir + ": a shard of '" + part.provenance.study + "', which this clothsim does not merge");
}

// Every item's summary lane, in item order.
std::vector<JsonObject> merged_lanes(const std::vector<ShardPart>& parts) {
  std::map<std::size_t, std::string> lanes;
  for (const ShardPart& p : parts) {
    std::map<std::size_t, std::string> mine;
    try {
      mine = analysis::Journal::read_lanes(p.dir);
    } catch (const std::runtime_error& e) {
      throw RuntimeFailure(e.what());
    }
    for (std::size_t item : p.provenance.items) {
      if (!mine.count(item))
        throw RuntimeFailure(p.dir + ": item " + std::to_string(item) + " has no summary lane (lanes/" +
                             std::to_string(item) + "); rerun the shard to write --summary");
      lanes[item] = mine[item];
    }
  }
  std::vector<JsonObject> out;
  for (const auto& [item, lane] : lanes) out.push_back(JsonObject::from_dump(lane));
  return out;
}

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
