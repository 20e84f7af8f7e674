#include "export_output.h"

#include <filesystem>

#include "clip/common/cli_common.h"
#include "export/mesh_export.h"

namespace clothsim::clip {
namespace fs = std::filesystem;
namespace {

class ExportOutput final : public FrameOutput {
 public:
  ExportOutput(const Model& model, ExportPath path, double fps, std::size_t lane, bool error)
      : export_(model, std::move(path), fps, error), lane_(lane) {}
  std::string what() const override { return "export"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.frame < 0) return;
    const LaneView& view = lanes[lane_];
    const std::vector<float>* error = view.field && !view.field->empty() ? view.field : nullptr;
    try {  // a lane that stands on one state (a long step, or diverged) exports it again
      export_.add(target.frame, view.frame->bodies, error);
    } catch (const ExportError& e) {
      throw RuntimeFailure(e.what());
    }
  }
  void finish() override {
    try {
      export_.finish();
    } catch (const ExportError& e) {
      throw RuntimeFailure(e.what());
    }
  }
  // Stopped: the per-frame files on disk stay; the PC2 or PVD index is not written, and said.
  void abandon(std::vector<std::string>& kept, std::vector<std::string>& lost) override {
    this->kept(kept);
    for (const std::string& f : export_.unwritten()) lost.push_back(f);
    const std::string gone = export_.lost();
    if (!gone.empty()) lost.push_back(gone);
  }
  bool needs_bodies() const override { return true; }
  void kept(std::vector<std::string>& kept) override {
    const std::string files = export_.written();
    if (!files.empty()) kept.push_back(files);
  }

 private:
  MeshExport export_;
  std::size_t lane_;
};

}  // namespace

std::vector<PathRole> export_roles(const std::string& path, const std::vector<std::string>& lanes, int spheres) {
  std::vector<PathRole> roles;
  std::vector<ExportPath> paths;
  try {
    paths = export_paths(path, lanes);
  } catch (const UsageError&) {
    return roles;
  } catch (const ExportError&) {
    return roles;
  }
  for (const ExportPath& p : paths) {
    for (const std::string& file : p.final_files(spheres)) roles.push_back({file, "--export"});
    // The series' folder claims its names: NAME_*.EXT (OBJ, PLY) or NAME/cloth_*.vtp (PVD).
    if (!p.dir.empty()) roles.push_back({p.dir, "--export", true, p.series_prefixes(spheres), p.suffix});
  }
  return roles;
}

std::vector<ExportPath> export_paths(const std::string& path, const std::vector<std::string>& lanes) {
  if (path.empty()) return {};
  ExportPath given;
  try {
    given = parse_export_path(path);
  } catch (const ExportError& e) {
    throw UsageError(e.what());
  }
  if (lanes.empty()) return {given};
  std::vector<ExportPath> out;
  for (const std::string& lane : lanes) {
    if (given.format == ExportFormat::Obj || given.format == ExportFormat::Ply) {
      const fs::path p(path);
      out.push_back(parse_export_path(((p.has_parent_path() ? p.parent_path() : fs::path(".")) / lane / p.filename()).string()));
    } else {
      out.push_back(parse_export_path(given.stem + "." + lane + fs::path(path).extension().string()));
    }
  }
  return out;
}

std::vector<ExportPath> checked_export_paths(const std::string& path, const std::vector<std::string>& lanes,
                                             int spheres) {
  const std::vector<ExportPath> paths = export_paths(path, lanes);
  for (const ExportPath& p : paths)
    for (const std::string& file : p.final_files(spheres)) require_writable_parent(file, "--export");
  for (const ExportPath& p : paths) {
    if (p.dir.empty()) continue;
    ensure_directory(p.dir, "--export");
    if (!no_overwrite()) continue;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(p.dir, ec))
      for (const std::string& prefix : p.series_prefixes(spheres))
        if (entry.path().filename().string().rfind(prefix, 0) == 0 && entry.path().extension() == p.suffix)
          throw UsageError("--export: " + p.dir + " already holds " + entry.path().filename().string() +
                           ", and -n/--no-overwrite keeps it");
  }
  return paths;
}

void add_export_outputs(FramePipeline& pipeline, const std::vector<ExportPath>& paths, const Model& model,
                        const std::vector<const Model*>& lane_models, double fps, bool error) {
  for (std::size_t i = 0; i < paths.size(); ++i)
    pipeline.add(std::make_unique<ExportOutput>(i < lane_models.size() ? *lane_models[i] : model, paths[i], fps, i, error));
}

}  // namespace clothsim::clip
