// The cost-balanced split and the shard record: every item in exactly one shard, the
// dearest items spread rather than dealt round-robin, and K/N read from Slurm's variables.
#include "study/shard.h"

#include <gtest/gtest.h>

#include <map>
#include <numeric>

#include "study/study.h"

namespace clothsim::analysis {
namespace {

EnvLookup env(std::map<std::string, std::string> vars) {
  return [vars = std::move(vars)](const char* name) -> const char* {
    const auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.c_str();
  };
}

double load(const std::vector<double>& costs, Shard s) {
  double sum = 0.0;
  for (std::size_t i : shard_items(costs, s)) sum += costs[i];
  return sum;
}

TEST(ShardSplit, PutsEveryItemInExactlyOneShard) {
  const std::vector<double> costs{5, 1, 9, 3, 3, 7, 2, 8, 1, 1, 4};
  std::vector<int> seen(costs.size(), 0);
  for (int k = 1; k <= 4; ++k)
    for (std::size_t i : shard_items(costs, {k, 4})) ++seen[i];
  for (int count : seen) EXPECT_EQ(count, 1);
}

TEST(ShardSplit, BalancesCostWhereRoundRobinWouldNot) {
  // A stiffness sweep: every fourth search dear. Round-robin gives them all to shard 1.
  std::vector<double> costs;
  for (int i = 0; i < 16; ++i) costs.push_back(i % 4 == 0 ? 100.0 : 1.0);
  const double total = std::accumulate(costs.begin(), costs.end(), 0.0);
  for (int k = 1; k <= 4; ++k) EXPECT_LE(load(costs, {k, 4}), total / 4 + 100.0 / 4 + 3.0) << "shard " << k;
  for (int k = 1; k <= 4; ++k) {  // one dear item each
    int dear = 0;
    for (std::size_t i : shard_items(costs, {k, 4})) dear += costs[i] > 1.0 ? 1 : 0;
    EXPECT_EQ(dear, 1) << "shard " << k;
  }
}

TEST(ShardSplit, IsTheSameInEveryProcessAndAllowsMoreShardsThanItems) {
  const std::vector<double> costs{2, 2, 2};
  EXPECT_EQ(assign_shards(costs, 5), assign_shards(costs, 5));
  EXPECT_TRUE(shard_items(costs, {5, 5}).empty());
  EXPECT_EQ(shard_items(costs, {1, 1}).size(), 3u);
}

TEST(ShardOption, ReadsKOverNAndRefusesOthers) {
  const EnvLookup none = env({});
  EXPECT_EQ(parse_shard("2/4", none).index, 2);
  EXPECT_EQ(parse_shard("2/4", none).count, 4);
  for (const char* bad : {"0/4", "5/4", "2", "a/b", "2/0", "-1/4", "2/4/1", ""})
    EXPECT_THROW(parse_shard(bad, none), StudyError) << bad;
}

TEST(ShardOption, AutoReadsSlurmsArrayVariables) {
  const Shard s = parse_shard("auto", env({{"SLURM_ARRAY_TASK_ID", "12"}, {"SLURM_ARRAY_TASK_COUNT", "4"},
                                           {"SLURM_ARRAY_TASK_MIN", "10"}}));
  EXPECT_EQ(s.index, 3);
  EXPECT_EQ(s.count, 4);
  EXPECT_EQ(parse_shard("auto", env({{"SLURM_ARRAY_TASK_ID", "0"}, {"SLURM_ARRAY_TASK_COUNT", "2"}})).index, 1);
  EXPECT_THROW(parse_shard("auto", env({})), StudyError);
  EXPECT_THROW(parse_shard("auto", env({{"SLURM_ARRAY_TASK_ID", "6"}, {"SLURM_ARRAY_TASK_COUNT", "4"},
                                        {"SLURM_ARRAY_TASK_MIN", "0"}})),
               StudyError);  // 0-7:2 has 4 tasks with ids up to 6
}

TEST(ShardProvenance, ReadsBackWhatItWrites) {
  Provenance p;
  p.study = "stability";
  p.version = "0.1.0";
  p.scene = "scenes/drape.yaml";
  p.scene_hash = hash_text("scene");
  p.plan_hash = hash_text("plan");
  p.title = "drape (T = 0.1 s)";
  p.command = "clothsim stability scenes/drape.yaml --shard 2/3";
  p.header = "param,value,integrator";
  p.shard = {2, 3};
  p.total_items = 7;
  p.items = {1, 4, 6};
  const Provenance q = parse_provenance(provenance_text(p));
  EXPECT_EQ(provenance_mismatch(p, q), "");
  EXPECT_EQ(q.command, p.command);
  EXPECT_EQ(q.items, p.items);
  EXPECT_EQ(q.shard.index, 2);
  EXPECT_EQ(q.title, p.title);
}

TEST(ShardProvenance, NamesTheFirstFieldThatDiffers) {
  Provenance a;
  a.study = "bench";
  a.version = "0.1.0";
  a.header = "h";
  Provenance b = a;
  b.shard = {1, 1};
  b.command = "another";
  EXPECT_EQ(provenance_mismatch(a, b), "");
  b.scene_hash = "x";
  EXPECT_EQ(provenance_mismatch(a, b), "scene_hash");
  b.version = "0.2.0";
  EXPECT_EQ(provenance_mismatch(a, b), "version");
  EXPECT_THROW(parse_provenance("study: bench\n"), StudyError);
  EXPECT_THROW(parse_provenance("clothsim-shard: 1\nstudy: bench\nheader: h\nitems: 1\nbogus: 2\n"), StudyError);
}

TEST(ShardHash, DiffersForDifferentBytes) {
  EXPECT_EQ(hash_text("abc"), hash_text("abc"));
  EXPECT_NE(hash_text("abc"), hash_text("abd"));
  EXPECT_EQ(hash_text("").size(), 16u);
}

}  // namespace
}  // namespace clothsim::analysis
