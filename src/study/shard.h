// Sharded studies: one study's work items split over N processes (Slurm array tasks), each
// writing its part beside a record of what it is a part of, so `clothsim merge` can join
// the parts into what one process writes, and refuse parts that do not belong together.
//
// The split balances estimated cost, not counts: items go, dearest first, to the shard
// with the least cost so far (longest-processing-time first; within 4/3 of the best split).
// Round-robin would give one shard every stiff case of a stiffness sweep, whose searches
// cost orders of magnitude more than the soft ones. Ties go to the lower item and shard,
// so every shard computes the same split from the same plan.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace clothsim::analysis {

// Shard K of N, K from 1.
struct Shard {
  int index = 1;
  int count = 1;
};

// "K/N" (1 <= K <= N), or "auto": K and N from Slurm's array variables (K = ID - MIN + 1,
// N = COUNT). Throws StudyError naming the problem. `env` reads a variable (nullptr: unset).
using EnvLookup = std::function<const char*(const char*)>;
Shard parse_shard(const std::string& text, const EnvLookup& env);
std::string shard_text(Shard s);  // "2/4"

// Which shard (0-based) runs each item, balanced by `costs` (one per item, >= 0).
std::vector<int> assign_shards(const std::vector<double>& costs, int count);
// The items shard `s` runs, ascending.
std::vector<std::size_t> shard_items(const std::vector<double>& costs, Shard s);

// FNV-1a 64, as 16 hex digits: the hashes provenance records (not a security measure).
std::string hash_text(const std::string& bytes);

// What a shard is a part of. Two shards merge only when every field but `shard`, `command`
// and `items` is equal.
struct Provenance {
  std::string study;       // "stability", "bench"
  std::string version;     // clothsim's
  std::string scene;       // the scene file as given
  std::string scene_hash;  // hash of the scene file's bytes and the --set list
  std::string plan_hash;   // hash of the study's resolved options and item list
  std::string title;       // the plot's title
  std::string command;     // the full command line
  std::string header;      // the CSV header the study writes
  Shard shard;
  std::size_t total_items = 0;     // in the whole study
  std::vector<std::size_t> items;  // this shard's, ascending
};

std::string provenance_text(const Provenance& p);
// Throws StudyError "LINE: what is wrong" on a malformed record.
Provenance parse_provenance(const std::string& text);
// The first field (besides shard, command, items) where `a` and `b` differ, "" when none:
// "scene_hash", "version", ...
std::string provenance_mismatch(const Provenance& a, const Provenance& b);

}  // namespace clothsim::analysis
