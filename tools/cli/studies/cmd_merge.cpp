// clothsim merge SHARD... [--csv FILE] [--plot FILE.png]
//
// Joins the parts of a sharded study (bench, stability or converge run with --shard K/N, each writing
// a directory F.shard-K-of-N/, study_shard.h) into the CSV the study writes in one process:
// the same header, the same rows in the same order (timing columns aside, which measure
// the machine each part ran on). Without --csv the CSV goes to stdout.
//
// Refuses, with one line naming the file: a directory that is not a shard, and shards of
// different studies, scenes, options, versions or shard counts. Lists every missing and
// incomplete shard and exits 1 without writing anything.
//
// A merged bench ends as the single-process one does: a reference not converged against the
// smallest error keeps the CSV, draws no plot and exits 1.
//
// Exit codes: 0; 2 bad options or shards that do not belong together; 1 missing or
// incomplete shards, a bench reference not converged, I/O, the plot.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>

#include "study_common.h"
#include "study_shard.h"
#include "cli/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/progress.h"
#include "study/study.h"
#include "study/work_precision.h"

namespace clothsim::cli {
namespace {

struct MergeOptions {
  std::vector<std::string> shards;
  std::string csv, plot;
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

// One CSV line's cells (RFC 4180 quotes, as csv_text writes them).
std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') cells.back() += c, ++i;
    else if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) cells.emplace_back();
    else cells.back() += c;
  }
  return cells;
}

// bench's last check, which needs every error (work_precision.h): the reference's own
// change at most reference_margin x the smallest RMS error. "" when it holds.
std::string bench_reference_problem(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_cells(line);
  const auto column = [&](const char* name) { return std::find(header.begin(), header.end(), name) - header.begin(); };
  const std::size_t rms_at = column("rms_error"), change_at = column("reference_change");
  double smallest = NAN, change = NAN;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = csv_cells(line);
    if (cells.size() != header.size()) continue;
    const double rms = std::strtod(cells[rms_at].c_str(), nullptr);
    if (std::isfinite(rms) && !(smallest <= rms)) smallest = rms;
    change = std::strtod(cells[change_at].c_str(), nullptr);
  }
  const double margin = analysis::WorkPrecisionSpec{}.reference_margin;
  char why[300] = "";
  if (std::isnan(change))
    std::snprintf(why, sizeof why, "the reference runs did not both reach T (see a shard's log)");
  else if (std::isfinite(smallest) && change > margin * smallest)
    std::snprintf(why, sizeof why, "the reference is not converged: halving its step moved the particles by %.3g m "
                  "RMS, more than %g x the smallest error reported (%.3g m)", change, margin, smallest);
  return why;
}

int merge_command(const MergeOptions& o) {
  refuse_shared_outputs({{o.csv, "--csv"}, {o.plot, "--plot"}});
  if (!o.csv.empty()) require_writable_parent(o.csv, "--csv");
  std::vector<ShardPart> parts;
  for (const std::string& dir : o.shards) parts.push_back(read_part(dir));
  check_same_study(parts);
  const std::string missing = missing_parts(parts);
  if (!missing.empty()) {
    std::fputs(missing.c_str(), stderr);
    throw RuntimeFailure("merge: the study is not complete (above); nothing written");
  }
  std::unique_ptr<PlotScript> plot;
  const analysis::Provenance& p = parts.front().provenance;
  if (!o.plot.empty())
    plot = std::make_unique<PlotScript>(p.study == "bench"      ? "plot_work_precision.py"
                                        : p.study == "converge" ? "plot_convergence.py"
                                                                : "plot_stability.py",
                                        o.plot);
  const std::string csv = merged_csv(parts);
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    std::fputs(csv.c_str(), file.stream());
    file.commit();
  };
  if (o.csv.empty()) std::fputs(csv.c_str(), stdout);
  else write_to(o.csv);
  std::fprintf(o.csv.empty() ? stderr : stdout, "merge: %s of %s, %zu shards, %zu rows%s%s\n", p.study.c_str(),
               p.scene.c_str(), parts.size(), p.total_items, o.csv.empty() ? "" : " -> ", o.csv.c_str());
  const std::string reference = p.study == "bench" ? bench_reference_problem(csv) : "";
  if (!reference.empty())  // as the single-process bench: the CSV stays for inspection, no plot
    throw RuntimeFailure(p.scene + ": " + reference + (o.csv.empty() ? "" : " (kept for inspection: " + o.csv + ")") +
                         "; no plot drawn");
  if (plot) plot->draw_from_csv(o.csv, write_to, {"--title", p.title});
  return kOk;
}

}  // namespace

void add_merge_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* sub = app.add_subcommand(
      "merge", "Join the shards of a sharded bench, stability or converge study (--shard K/N) into its CSV and plot");
  sub->add_option("shards", o->shards, "The shard directories (F.shard-K-of-N), all of one study")
      ->required()
      ->type_name("SHARD...");
  sub->add_option("--csv", o->csv, "Write the merged CSV here (default: stdout)")->type_name("FILE.csv");
  sub->add_option("--plot", o->plot, "Draw the study's figure (needs python3-matplotlib)")->type_name("FILE.png");
  add_no_overwrite_option(sub);
  sub->callback([o, &command] { command = [o] { return merge_command(*o); }; });
}

}  // namespace clothsim::cli
