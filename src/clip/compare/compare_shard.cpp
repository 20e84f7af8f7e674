#include "compare_shard.h"

#include <cstdio>
#include <filesystem>

#include "clip/common/cli_common.h"
#include "clip/studies/study_shard.h"
#include "study/shard.h"
#include "study/study.h"
#include "study/work_precision.h"

namespace clothsim::clip {
namespace {

// A pixel of a tile counted as one particle force evaluation, as golden check counts it
// (docs/cluster.md).
constexpr double kPixelCost = 1.0;

void check_scale(const FramesShardPlan& plan) {
  if (plan.scale_from_data)
    throw UsageError("--shard: the colour scale would be chosen from this part's lanes only, so its tiles would differ "
                     "from one process's; give --color-range LO,HI (or --color checker)");
}

}  // namespace

void check_frames_shard_outputs(const std::string& frames_dir, bool other_outputs) {
  if (frames_dir.empty()) throw UsageError("--shard: compare takes it with --frames DIR only (a part writes its lanes' PNGs)");
  if (other_outputs)
    throw UsageError("--shard: --video, --sheet, --still and --summary draw every lane; a part writes --frames only "
                     "(`clothsim encode` composes the parts' folders into the clip)");
}

std::vector<std::size_t> frames_shard_lanes(const FramesShardPlan& plan, const std::vector<Lane>& lanes,
                                            const std::vector<std::string>& lane_dirs) {
  const analysis::Shard shard = parse_shard_option(plan.shard);
  check_scale(plan);
  std::vector<double> costs;
  for (const Lane& l : lanes)
    costs.push_back(analysis::cost_estimate(l.kind, plan.duration, l.dt) * plan.particles +
                    kPixelCost * static_cast<double>(plan.frames) * plan.tile_width * plan.tile_height);
  const std::vector<std::size_t> mine = analysis::shard_items(costs, shard);
  std::string dirs;
  for (std::size_t i : mine)
    dirs += (dirs.empty() ? "" : ", ") + (std::filesystem::path(plan.frames_dir) / lane_dirs[i]).string();
  std::printf("shard %s of compare: %zu of %zu lanes%s%s\n", analysis::shard_text(shard).c_str(), mine.size(),
              lanes.size(), mine.empty() ? "" : "; writing ", dirs.c_str());
  std::fflush(stdout);
  return mine;
}

}  // namespace clothsim::clip
