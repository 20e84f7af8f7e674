#include "study_merge.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "clip/common/cli_common.h"
#include "clip/golden/golden_report.h"
#include "clip/studies/study_common.h"
#include "clip/studies/study_shard.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"
#include "study/journal.h"
#include "study/study.h"
#include "study/work_precision.h"

namespace clothsim::clip {

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

namespace {

// "out.csv.shard-3-of-4" beside a given part's name, for the list of missing parts.
std::string sibling_name(const ShardPart& part, int index) {
  std::string dir = part.dir;
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  const std::string mine = ".shard-" + std::to_string(part.provenance.shard.index) + "-of-";
  const std::size_t at = dir.rfind(mine);
  if (at == std::string::npos) return "";
  return dir.substr(0, at) + ".shard-" + std::to_string(index) + "-of-" + std::to_string(part.provenance.shard.count);
}

}  // namespace

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

std::string part_csv(const ShardPart& part) {
  std::string csv = part.provenance.header + "\n";
  for (const auto& [item, row] : part.rows) csv += row;  // a std::map: in item order
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

namespace {

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

const StudyMerge kStudyMerges[] = {
    {"stability", "plot_stability.py", true, stability_keys, nullptr},
    {"bench", "plot_work_precision.py", true, bench_keys, bench_conclusion},
    {"golden", nullptr, false, golden_keys, golden_conclusion},
    {"converge", "plot_convergence.py", true, nullptr, nullptr},
};

}  // namespace

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

}  // namespace clothsim::clip
