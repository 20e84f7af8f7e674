// What `--export PATH` names, by its extension (docs/cli.md, "Mesh export"):
//   DIR/NAME%05d.obj, DIR/NAME%05d.ply  a file per output frame (printf's %0Nd, N from 1 to 9);
//                                       sphere s in its own series, DIR/NAMEsphere<s>_%05d.EXT
//   NAME.pc2                            Point Cache 2 of the cloth beside NAME.obj, its rest mesh
//                                       (Blender's Mesh Cache modifier); sphere s in
//                                       NAME.sphere<s>.pc2 beside NAME.sphere<s>.obj
//   NAME.pvd                            a ParaView collection indexing NAME/cloth_%05d.vtp and
//                                       NAME/sphere<s>_%05d.vtp, one part (block) each
// Parsing is all it does: no file is touched (the caller checks and creates, before any work).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace clothsim {

// A bad export path or a failed write: the whole one-line message.
struct ExportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class ExportFormat { Obj, Ply, Pc2, Pvd };

struct ExportPath {
  ExportFormat format = ExportFormat::Obj;
  std::string path;         // as given
  std::string dir;          // where the per-frame files go ("." for none given); "" for PC2
  std::string prefix;       // sequences: the file name before the number ("frame_"); PVD: "cloth_"
  std::string suffix;       // ".obj", ".ply", ".vtp"
  int digits = 5;           // of the frame number
  std::string stem;         // PC2 and PVD: PATH without its extension
  // The file of frame `frame` of the cloth (sphere < 0) or of sphere `sphere`.
  std::string frame_file(int frame, int sphere = -1) const;
  // The files named once the run is through (PC2 and its rest meshes, the PVD index), for
  // the checks before any work.
  std::vector<std::string> final_files(int spheres) const;
  // The per-frame series' file-name prefixes (cloth first), for the -n check of `dir`.
  std::vector<std::string> series_prefixes(int spheres) const;
};

// Throws ExportError("--export: ...") naming what is wrong: an unknown extension, a sequence
// without one %0Nd (or with any other %), a PC2 or PVD path with a %.
ExportPath parse_export_path(const std::string& path);

}  // namespace clothsim
