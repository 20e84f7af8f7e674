// The compare the CLI tests run: the drape at 9 x 9 particles over 0.2 s, 320x180, x264's
// fastest preset, plus a test's own arguments. Small enough for a test of a second or so.
#pragma once

#include <string>
#include <vector>

#include "cli/cli_process.h"

namespace clothsim::testing {

inline const std::string kDrape = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";

inline CliResult compare_small(const std::vector<std::string>& extra) {
  std::vector<std::string> args = {"compare", kDrape, "--set", "cloth.particles=[9,9]", "--duration", "0.2",
                                   "--width", "320", "--height", "180", "--preset", "ultrafast"};
  args.insert(args.end(), extra.begin(), extra.end());
  return run_clothsim(args);
}

}  // namespace clothsim::testing
