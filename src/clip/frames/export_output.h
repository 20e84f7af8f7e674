// --export of `run` and `compare`: each lane's cloth and spheres at every clip frame, written
// by the export library (export/mesh_export.h). The option's checks run before any work.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "frame_pipeline.h"
#include "clip/common/cli_common.h"
#include "core/model/model.h"
#include "export/export_path.h"

namespace CLI {
class App;
}

namespace clothsim::clip {

// compare's per-lane paths, from its lane directories ("rk4", "rk4@1e-4"): a sequence
// DIR/frame_%05d.obj goes to DIR/LANE/frame_%05d.obj; NAME.pc2 to NAME.LANE.pc2 (beside
// NAME.LANE.obj); NAME.pvd to NAME.LANE.pvd (over NAME.LANE/). run: one lane, `lanes` empty,
// the path as given.
std::vector<ExportPath> export_paths(const std::string& path, const std::vector<std::string>& lanes);

// What export_paths(path, lanes) writes, for refuse_clashing_paths: the files named at the end
// (PC2 and its rest meshes, the PVD index) and each sequence's directory, which claims its
// frame_* files. Empty for a malformed path (checked_export_paths refuses it).
std::vector<PathRole> export_roles(const std::string& path, const std::vector<std::string>& lanes, int spheres);

// export_paths(path, lanes), checked before any work: the path's form (UsageError), every file
// named at the end writable (require_writable_parent: -n refuses one that exists), the
// per-frame directories created, and with -n, a directory holding that series already refused.
std::vector<ExportPath> checked_export_paths(const std::string& path, const std::vector<std::string>& lanes,
                                             int spheres);

// An output per lane i writing its frames to paths[i], of lane_models[i] (compare --vary) or
// `model`, with the error field when the pipeline colours by error (`error`: LaneView::field).
// The models must outlive the pipeline.
void add_export_outputs(FramePipeline& pipeline, const std::vector<ExportPath>& paths, const Model& model,
                        const std::vector<const Model*>& lane_models, double fps, bool error);

}  // namespace clothsim::clip
