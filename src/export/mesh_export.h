// Mesh export (`run --export`, `compare --export`, the Python module): the cloth and the
// spheres of every output frame, in the format the path names (export_path.h), each file
// written whole or not at all (io/output_file.h):
//   OBJ, PLY, VTP  a file per frame per object, named as it is written;
//   PC2            the caches and their rest meshes (the first frame's), named at finish();
//   PVD            the index, named at finish(), over the .vtp files already named.
// A run that stops keeps the per-frame files written so far, and no PC2 or PVD. A sequence
// finished removes a longer earlier run's files of its series past its last frame; it never
// finishes over files of its own that are gone (a folder moved or removed during the run).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/model/model.h"
#include "core/model/state.h"
#include "export/export_path.h"

namespace clothsim {

class MeshExport {
 public:
  // Frame k of the export is at t = k / fps (the PC2's sample rate is one frame). `error`:
  // whether add() is given the error field. Creates nothing yet (the first add() makes the
  // per-frame directory if missing). `model` must outlive it.
  MeshExport(const Model& model, ExportPath path, double fps, bool error);
  ~MeshExport();  // without finish(): whatever is not named yet is dropped
  MeshExport(const MeshExport&) = delete;
  MeshExport& operator=(const MeshExport&) = delete;

  // Frame `frame` (0, 1, 2 ... in order): the cloth and spheres of `bodies` (x, v and t
  // used), with the error field (P values, m) when the export has one. Throws ExportError
  // ("cannot write PATH: reason").
  void add(int frame, const State& bodies, const std::vector<float>* error = nullptr);
  // Names what is named at the end (PC2 and its meshes, the PVD index), then removes the
  // series' later frames of an earlier run. Throws ExportError, also when per-frame files it
  // wrote are gone (and then names nothing).
  void finish();
  // What stays on disk: "12 OBJ files in out/", "c.pc2, c.obj" ("" for nothing): the files
  // written that are still there.
  std::string written() const;
  // What finish() names, until it has: the PC2s and their meshes, or the PVD index.
  std::vector<std::string> unwritten() const;
  // Per-frame files written and gone since: "464 OBJ files gone from ex/ (moved or removed during
  // the run)", or "".
  std::string lost() const;
  // The same as paths: every per-frame file in the order written, then what finish() named.
  std::vector<std::string> written_files() const;
  int frames() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim
