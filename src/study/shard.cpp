#include "shard.h"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "study.h"

namespace clothsim::analysis {
namespace {

// A whole number in [lo, hi] from text, or -1.
long whole_number(const std::string& text, long lo, long hi) {
  if (text.empty() || text.size() > 9 || !std::all_of(text.begin(), text.end(), ::isdigit)) return -1;
  const long n = std::stol(text);
  return n >= lo && n <= hi ? n : -1;
}

Shard shard_from_slurm(const EnvLookup& env) {
  const char* id = env("SLURM_ARRAY_TASK_ID");
  const char* count = env("SLURM_ARRAY_TASK_COUNT");
  const char* min = env("SLURM_ARRAY_TASK_MIN");
  if (!id || !count)
    throw StudyError("auto: SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT are not set (not a Slurm array task); "
                     "give K/N");
  const long n = whole_number(count, 1, 100000);
  const long i = whole_number(id, 0, 100000000);
  const long lo = min ? whole_number(min, 0, 100000000) : 0;
  if (n < 0 || i < 0 || lo < 0) throw StudyError("auto: the SLURM_ARRAY_TASK_* variables are not whole numbers");
  if (i < lo || i - lo >= n)
    throw StudyError("auto: task " + std::to_string(i) + " is not within " + std::to_string(lo) + ".." +
                     std::to_string(lo + n - 1) + " (an array with a step, such as 0-7:2, is not supported)");
  return {static_cast<int>(i - lo + 1), static_cast<int>(n)};
}

}  // namespace

Shard parse_shard(const std::string& text, const EnvLookup& env) {
  if (text == "auto") return shard_from_slurm(env);
  const std::size_t slash = text.find('/');
  const long n = slash == std::string::npos ? -1 : whole_number(text.substr(slash + 1), 1, 100000);
  const long k = slash == std::string::npos ? -1 : whole_number(text.substr(0, slash), 1, 100000);
  if (n < 0 || k < 0) throw StudyError("'" + text + "' is not K/N (two whole numbers, 1 <= K <= N) or auto");
  if (k > n) throw StudyError("shard " + text + ": K must be at most N");
  return {static_cast<int>(k), static_cast<int>(n)};
}

std::string shard_text(Shard s) { return std::to_string(s.index) + "/" + std::to_string(s.count); }

std::vector<int> assign_shards(const std::vector<double>& costs, int count) {
  std::vector<std::size_t> order(costs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return costs[a] > costs[b]; });
  std::vector<double> load(static_cast<std::size_t>(std::max(count, 1)), 0.0);
  std::vector<int> shard_of(costs.size(), 0);
  for (std::size_t item : order) {
    const auto lightest = std::min_element(load.begin(), load.end());  // first of equals: the lowest shard
    *lightest += costs[item];
    shard_of[item] = static_cast<int>(lightest - load.begin());
  }
  return shard_of;
}

std::vector<std::size_t> shard_items(const std::vector<double>& costs, Shard s) {
  const std::vector<int> shard_of = assign_shards(costs, s.count);
  std::vector<std::size_t> items;
  for (std::size_t i = 0; i < shard_of.size(); ++i)
    if (shard_of[i] == s.index - 1) items.push_back(i);
  return items;
}

std::string hash_text(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

std::string provenance_text(const Provenance& p) {
  std::ostringstream out;
  out << "clothsim-shard: 1\n"
      << "study: " << p.study << "\nversion: " << p.version << "\nscene: " << p.scene
      << "\nscene_hash: " << p.scene_hash << "\nplan_hash: " << p.plan_hash << "\ntitle: " << p.title
      << "\ncommand: " << p.command << "\nheader: " << p.header << "\nshard: " << shard_text(p.shard)
      << "\ntotal_items: " << p.total_items << "\nitems:";
  for (std::size_t i : p.items) out << ' ' << i;
  out << '\n';
  return out.str();
}

Provenance parse_provenance(const std::string& text) {
  Provenance p;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  bool seen_items = false;
  const auto bad = [&](const std::string& what) { return StudyError("line " + std::to_string(number) + ": " + what); };
  while (std::getline(in, line)) {
    ++number;
    const std::size_t colon = line.find(": ");
    const std::string key = line.substr(0, colon == std::string::npos ? line.find(':') : colon);
    const std::string value = colon == std::string::npos ? "" : line.substr(colon + 2);
    if (number == 1 && line != "clothsim-shard: 1") throw bad("not a clothsim shard record");
    else if (key == "study") p.study = value;
    else if (key == "version") p.version = value;
    else if (key == "scene") p.scene = value;
    else if (key == "scene_hash") p.scene_hash = value;
    else if (key == "plan_hash") p.plan_hash = value;
    else if (key == "title") p.title = value;
    else if (key == "command") p.command = value;
    else if (key == "header") p.header = value;
    else if (key == "shard") p.shard = parse_shard(value, [](const char*) { return nullptr; });
    else if (key == "total_items") {
      const long n = whole_number(value, 0, 100000000);
      if (n < 0) throw bad("total_items is not a whole number");
      p.total_items = static_cast<std::size_t>(n);
    }
    else if (key == "items") {
      std::istringstream items(line.substr(line.find(':') + 1));
      for (std::size_t i; items >> i;) p.items.push_back(i);
      seen_items = true;
    } else if (number > 1) throw bad("unknown key '" + key + "'");
  }
  if (!seen_items || p.study.empty() || p.header.empty()) throw bad("the record is cut short");
  return p;
}

std::string provenance_mismatch(const Provenance& a, const Provenance& b) {
  if (a.study != b.study) return "study";
  if (a.version != b.version) return "version";
  if (a.scene_hash != b.scene_hash) return "scene_hash";
  if (a.plan_hash != b.plan_hash) return "plan_hash";
  if (a.header != b.header) return "header";
  if (a.shard.count != b.shard.count || a.total_items != b.total_items) return "shard count";
  return "";
}

}  // namespace clothsim::analysis
