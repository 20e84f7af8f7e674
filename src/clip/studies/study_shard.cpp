#include "study_shard.h"

#include <cstdlib>
#include <filesystem>

#include "clip/common/cli_common.h"
#include "study/study.h"

namespace clothsim::clip {
namespace {

namespace fs = std::filesystem;

const char* env_lookup(const char* name) { return std::getenv(name); }

// The directory's record must be this plan's: a rerun continues it, anything else is refused.
void check_existing(const std::string& dir, const analysis::Provenance& mine) {
  const std::string path = dir + "/provenance";
  if (!fs::exists(path)) return;
  analysis::Provenance theirs;
  try {
    theirs = analysis::parse_provenance(analysis::read_whole_file(path));
  } catch (const std::exception& e) {
    throw UsageError(path + ": " + e.what() + "; remove " + dir);
  }
  const std::string field = analysis::provenance_mismatch(mine, theirs);
  if (!field.empty() || theirs.shard.index != mine.shard.index)
    throw UsageError(path + ": holds a part of another study (" + (field.empty() ? "shard" : field) +
                     " differs); remove " + dir + " or write elsewhere");
}

}  // namespace

analysis::Shard parse_shard_option(const std::string& text) {
  try {
    return analysis::parse_shard(text, env_lookup);
  } catch (const analysis::StudyError& e) {
    throw UsageError(std::string("--shard: ") + e.what());
  }
}

std::string shard_dir(const std::string& csv, analysis::Shard shard) {
  return csv + ".shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count);
}

StudyShard::StudyShard(const std::string& shard_option, const std::string& csv, const std::string& plot,
                       const std::string& summary, const ShardPlan& plan) {
  const analysis::Shard shard = parse_shard_option(shard_option);
  if (csv.empty()) throw UsageError("--shard: needs --csv F (the part is written to F.shard-K-of-N/)");
  if (!plot.empty()) throw UsageError("--plot: a shard draws no plot; give --plot to clothsim merge");
  if (!summary.empty()) throw UsageError("--summary: a shard writes no summary; give --summary to clothsim merge");
  require_writable_parent(csv, "--csv");
  analysis::Provenance& p = provenance_;
  p.study = plan.study;
  p.version = CLOTHSIM_VERSION;
  p.scene = plan.scene_path;
  p.scene_hash = scene_hash(plan.scene_path, plan.sets);
  p.plan_hash = analysis::hash_text(plan.plan + "\n" + plan.header);
  p.title = plan.title;
  p.command = full_command();
  p.header = plan.header;
  p.shard = shard;
  p.total_items = plan.costs.size();
  p.items = analysis::shard_items(plan.costs, shard);
  const std::string dir = shard_dir(csv, shard);
  check_existing(dir, p);
  try {
    journal_ = std::make_unique<analysis::Journal>(dir);
    analysis::write_file_atomically(dir + "/provenance", analysis::provenance_text(p));
  } catch (const std::runtime_error& e) {
    throw RuntimeFailure(e.what());
  }
  for (std::size_t item : p.items)
    if (!journal_->done(item)) todo_.push_back(item);
  std::printf("shard %s of %s: %zu of %zu items, %zu finished before, %zu to run; writing %s/\n",
              analysis::shard_text(shard).c_str(), plan.study.c_str(), p.items.size(), p.total_items,
              p.items.size() - todo_.size(), todo_.size(), dir.c_str());
  std::fflush(stdout);
}

void StudyShard::record(std::size_t item, const std::string& row, const std::string& lane) {
  try {
    journal_->record(item, row, lane);
  } catch (const std::runtime_error& e) {
    throw RuntimeFailure(e.what());
  }
}

int StudyShard::finish() const {
  std::size_t finished = 0;
  for (std::size_t item : provenance_.items) finished += journal_->done(item) ? 1 : 0;
  std::printf("shard %s: %zu of %zu items finished in %s/\n", analysis::shard_text(provenance_.shard).c_str(),
              finished, provenance_.items.size(), journal_->dir().c_str());
  if (finished < provenance_.items.size())
    throw RuntimeFailure("interrupted: " + std::to_string(finished) + " of " + std::to_string(provenance_.items.size()) +
                         " items of shard " + analysis::shard_text(provenance_.shard) + " finished; kept in " +
                         journal_->dir() + "/ (a rerun of the same command runs the rest)");
  return kOk;
}

std::string written_text(const std::function<void(std::FILE*)>& write) {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* f = open_memstream(&buffer, &size);
  if (!f) throw RuntimeFailure("cannot open a memory stream");
  write(f);
  std::fclose(f);
  std::string text(buffer, size);
  std::free(buffer);
  return text;
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

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

std::string after_first_line(const std::string& text) {
  const std::size_t nl = text.find('\n');
  return nl == std::string::npos ? "" : text.substr(nl + 1);
}

std::string full_command() {
  std::string args, command;
  try {
    args = analysis::read_whole_file("/proc/self/cmdline");
  } catch (const std::exception&) {
    return "clothsim";
  }
  std::size_t at = 0;
  while (at < args.size()) {
    const std::size_t end = args.find('\0', at);
    const std::string arg = args.substr(at, end == std::string::npos ? std::string::npos : end - at);
    const bool quote = arg.empty() || arg.find_first_of(" \t'\"") != std::string::npos;
    command += (command.empty() ? "" : " ") + (quote ? "'" + arg + "'" : arg);
    for (char& c : command)
      if (c == '\n' || c == '\r') c = ' ';  // the record is one line per key
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return command;
}

std::string scene_hash(const std::string& path, const std::vector<std::string>& sets) {
  std::string bytes;
  try {
    bytes = analysis::read_whole_file(path);
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  for (const std::string& s : sets) bytes += "\n--set " + s;
  return analysis::hash_text(bytes);
}

}  // namespace clothsim::clip
