#include "export/export_path.h"

#include <cstdio>
#include <filesystem>

namespace clothsim {
namespace {

std::string extension_of(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  std::string lower;
  for (char c : ext) lower += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return lower;
}

std::string numbered(int frame, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%0*d", digits, frame);
  return text;
}

// DIR/NAME%0Nd.EXT -> dir, prefix, digits, suffix.
void parse_sequence(const std::string& path, ExportPath& out) {
  const std::filesystem::path p(path);
  const std::string name = p.filename().string();
  const std::size_t pct = name.find('%');
  const std::string usage = "--export: " + path + ": a sequence is named DIR/NAME%05d" + out.suffix +
                            " (one %0Nd for the frame number)";
  if (pct == std::string::npos || name.find('%', pct + 1) != std::string::npos) throw ExportError(usage);
  std::size_t i = pct + 1;
  if (i < name.size() && name[i] == '0') ++i;
  int digits = 0;
  while (i < name.size() && name[i] >= '0' && name[i] <= '9') digits = digits * 10 + (name[i++] - '0');
  if (i >= name.size() || name[i] != 'd' || digits < 1 || digits > 9) throw ExportError(usage);
  out.prefix = name.substr(0, pct);
  out.digits = digits;
  if (name.substr(i + 1) != out.suffix) throw ExportError(usage);
  out.dir = p.parent_path().empty() ? "." : p.parent_path().string();
  if (out.dir.find('%') != std::string::npos) throw ExportError(usage);
}

}  // namespace

ExportPath parse_export_path(const std::string& path) {
  ExportPath out;
  out.path = path;
  const std::string ext = extension_of(path);
  if (ext == ".obj" || ext == ".ply") {
    out.format = ext == ".obj" ? ExportFormat::Obj : ExportFormat::Ply;
    out.suffix = std::filesystem::path(path).extension().string();
    parse_sequence(path, out);
    return out;
  }
  if (ext != ".pc2" && ext != ".pvd")
    throw ExportError("--export: " + path +
                      ": unknown format (DIR/frame_%05d.obj, DIR/frame_%05d.ply, NAME.pc2 or NAME.pvd)");
  if (path.find('%') != std::string::npos)
    throw ExportError("--export: " + path + ": a " + ext + " file is one file, with no %0Nd in its name");
  out.format = ext == ".pc2" ? ExportFormat::Pc2 : ExportFormat::Pvd;
  out.stem = path.substr(0, path.size() - ext.size());
  if (std::filesystem::path(out.stem).filename().empty())
    throw ExportError("--export: " + path + ": the file needs a name before " + ext);
  if (out.format == ExportFormat::Pvd) {
    out.dir = out.stem;  // NAME/cloth_00000.vtp ...
    out.prefix = "cloth_";
    out.suffix = ".vtp";
  }
  return out;
}

std::string ExportPath::frame_file(int frame, int sphere) const {
  std::string name = prefix;
  if (sphere >= 0)
    name = format == ExportFormat::Pvd ? "sphere" + std::to_string(sphere) + "_"
                                       : prefix + "sphere" + std::to_string(sphere) + "_";
  return (std::filesystem::path(dir) / (name + numbered(frame, digits) + suffix)).string();
}

std::vector<std::string> ExportPath::final_files(int spheres) const {
  std::vector<std::string> files;
  if (format == ExportFormat::Pvd) files.push_back(path);
  if (format == ExportFormat::Pc2) {
    files = {path, stem + ".obj"};
    for (int s = 0; s < spheres; ++s) {
      const std::string sphere = stem + ".sphere" + std::to_string(s);
      files.push_back(sphere + ".pc2");
      files.push_back(sphere + ".obj");
    }
  }
  return files;
}

std::vector<std::string> ExportPath::series_prefixes(int spheres) const {
  if (format == ExportFormat::Pc2) return {};
  std::vector<std::string> out{prefix};
  const std::string base = format == ExportFormat::Pvd ? "" : prefix;
  for (int s = 0; s < spheres; ++s) out.push_back(base + "sphere" + std::to_string(s) + "_");
  return out;
}

}  // namespace clothsim
