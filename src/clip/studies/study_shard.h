// --shard K/N|auto on bench, stability and golden check (src/study/shard.h): the study's part this process
// runs, and where it goes. With --csv F, shard K of N writes the directory F.shard-K-of-N/:
// its provenance record and a journal of finished items (src/study/journal.h), each with its
// CSV row(s) and its --summary lane; `clothsim merge` joins the directories into F. A rerun of the same command (a
// requeued array task) finds the directory and runs only what it does not hold.
#pragma once

#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "study/journal.h"
#include "study/shard.h"

namespace clothsim::clip {

// What a study tells its shard about itself.
struct ShardPlan {
  std::string study;                  // "stability", "bench", "golden"
  std::string scene_path;             // as given
  std::vector<std::string> sets;      // --set, in order
  std::string plan;                   // the resolved options and item list, as text (hashed)
  std::string title;                  // the merged plot's title
  std::string header;                 // the CSV header
  std::vector<double> costs;          // one per item, in the study's row order
};

// --shard K/N or auto (from Slurm's array variables); UsageError naming --shard when bad.
analysis::Shard parse_shard_option(const std::string& text);

// "F.shard-2-of-4"
std::string shard_dir(const std::string& csv, analysis::Shard shard);

class StudyShard {
 public:
  // Parses --shard, refuses the options a shard does not write (--plot, --summary: merge's),
  // opens the directory and says on stdout what this part runs. UsageError on bad input,
  // including a directory holding a part of another study.
  StudyShard(const std::string& shard_option, const std::string& csv, const std::string& plot,
             const std::string& summary, const ShardPlan& plan);
  // This part's items that are not finished yet, ascending.
  const std::vector<std::size_t>& todo() const { return todo_; }
  // The item's CSV row(s) and its --summary lane (JsonObject::dump()), for merge.
  void record(std::size_t item, const std::string& row, const std::string& lane);
  const std::string& dir() const { return journal_->dir(); }
  // Says what is finished; RuntimeFailure (exit 130/143 when a signal stopped it) if not all.
  int finish() const;

 private:
  analysis::Provenance provenance_;
  std::unique_ptr<analysis::Journal> journal_;
  std::vector<std::size_t> todo_;
};

// The text a CSV writer writes to a stream (`write` is given a temporary one).
std::string written_text(const std::function<void(std::FILE*)>& write);
// One CSV line's cells (RFC 4180 quotes, as csv_text writes them).
std::vector<std::string> csv_cells(const std::string& line);
// Its first line (without the newline) and the rest.
std::string first_line(const std::string& text);
std::string after_first_line(const std::string& text);

// The command line of this process, as typed (arguments with spaces quoted).
std::string full_command();
// The scene file's bytes and the --set list: what the scene hash covers.
std::string scene_hash(const std::string& path, const std::vector<std::string>& sets);

}  // namespace clothsim::clip
