// compare --frames DIR --shard K/N|auto: part K of N of a comparison's lanes, each writing its
// PNGs to DIR/<lane>/ as one `compare --frames DIR` does, so `clothsim encode` composes the
// parts' folders into the clip one process's folders make (docs/cluster.md).
//
// Every part plans the whole comparison (the steps --match chooses, the reference, the grid
// and so the tile size) and then runs only its lanes, split by estimated cost (shard.h), not
// round-robin. A lane's pictures depend on the other lanes only through a colour scale taken
// from the data, so a part refuses that (give --color-range, or --color checker); the clip,
// the sheet, the still and the summary draw every lane, so a part refuses them too, before
// any planning (--match's pilot runs).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "clip/common/lanes.h"

namespace clothsim::clip {

// What the comparison would write and draw, for the checks.
struct FramesShardPlan {
  std::string shard;              // --shard's value
  std::string frames_dir;         // --frames
  bool scale_from_data = false;   // the tiles are coloured on a scale chosen from the lanes' data
  double duration = 0.0;          // s
  int particles = 0;
  long frames = 0;                // per lane
  int tile_width = 0, tile_height = 0;
};

// Before any planning: a part writes --frames and nothing else (UsageError otherwise).
void check_frames_shard_outputs(const std::string& frames_dir, bool other_outputs);

// This part's lanes (indices into `lanes`, ascending); says on stdout which. UsageError when
// the comparison cannot be split so (above).
std::vector<std::size_t> frames_shard_lanes(const FramesShardPlan& plan, const std::vector<Lane>& lanes,
                                            const std::vector<std::string>& lane_dirs);

}  // namespace clothsim::clip
