// Golden-image manifests: which scenes, run how, rendered at which times and sizes, compared
// with which tolerance. `clothsim golden check|update MANIFEST.yaml` reads one; the project's
// own golden tests are tests/golden/manifest.yaml. The format (docs/golden.md):
//
//   size: [320, 180]                      # default for entries, pixels
//   tolerance: {threshold: 16, max_rms: 2, max_over: 0.005}   # default: imgdiff's
//   goldens:
//     - scene: ../../scenes/drape.yaml    # relative to the manifest's directory
//       times: [1.5]                      # s; one image per time
//       integrator: rk4                   # optional: the scene's otherwise
//       dt: 1e-4                          # optional: the scene's otherwise
//       name: drape_rk4                   # optional: the scene file's stem otherwise
//       size: [640, 360]                  # optional
//       tolerance: {max_rms: 1}           # optional, per key
//
// Each image is NAME_tMSms.png beside the manifest (drape_t1500ms.png). Errors are the
// scene parser's: one line, "MANIFEST:LINE: KEY: what is wrong" (SceneError, exit 2).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/integrators/integrator_kind.h"
#include "render/image_diff.h"

namespace clothsim::clip {

struct GoldenEntry {
  std::string scene;                       // path, resolved against the manifest's directory
  std::string name;                        // image file stem
  // kind: still (the default) goldens what `run --still T` draws; compare goldens the grid
  // `compare --integrators LANES --still T` draws, its lanes matched on cost as compare does.
  bool compare = false;
  std::string integrators;                 // compare: the lanes, compare's --integrators text
  std::optional<IntegratorKind> integrator;
  std::optional<double> dt;                // s
  std::vector<double> times;               // s, ascending
  int width = 320, height = 180;           // pixels
  DiffTolerance tolerance;
  int line = 0;                            // of the entry in the manifest, for messages
  int dt_line = 0, times_line = 0;         // of its dt and times keys (0: as `line`)
};

struct GoldenManifest {
  std::string path;
  std::vector<GoldenEntry> entries;
};

// Throws SceneError (file, line, key) for anything wrong in the manifest itself: unknown or
// missing keys, wrong types, bad values, two entries writing the same image.
GoldenManifest load_golden_manifest(const std::string& path);

// Where the golden image of `entry` at time `t` lives: beside the manifest.
std::string golden_image_path(const GoldenManifest& manifest, const GoldenEntry& entry, double t);

}  // namespace clothsim::clip
