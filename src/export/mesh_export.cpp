#include "export/mesh_export.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "export/mesh_part.h"
#include "export/mesh_writers.h"
#include "io/output_file.h"

namespace clothsim {
namespace {

void write_whole(const std::string& path, const std::string& bytes) {
  try {
    OutputFile file(path);
    if (!write_all(file.fd(), bytes.data(), bytes.size()))
      throw OutputFileError("cannot write " + path + ": " + std::strerror(errno));
    file.commit();
  } catch (const OutputFileError& e) {
    throw ExportError(e.what());
  }
}

// A Point Cache 2 being written: the samples stream into the nameless file, the header's
// sample count is set at the end.
struct Pc2Stream {
  Pc2Stream(std::string cache, std::string mesh) : path(std::move(cache)), rest_path(std::move(mesh)) {}
  std::string path, rest_path;  // NAME.pc2, NAME.obj
  std::unique_ptr<OutputFile> file;
  std::string rest;  // the rest mesh's OBJ, of the first frame
  int points = 0, samples = 0;
  void add(const MeshPart& part, const std::string& comment) {
    if (!file) {
      file = std::make_unique<OutputFile>(path);
      points = static_cast<int>(part.points.size() / 3);
      rest = obj_text(part, comment);
      put(pc2_header(points, 0.0f, 1.0f, 0));
    }
    put(pc2_sample(part));
    ++samples;
  }
  void put(const std::string& bytes) {
    if (!write_all(file->fd(), bytes.data(), bytes.size()))
      throw OutputFileError("cannot write " + path + ": " + std::strerror(errno));
  }
  void finish() {
    if (!file) return;
    const std::string header = pc2_header(points, 0.0f, 1.0f, samples);
    if (::pwrite(file->fd(), header.data(), header.size(), 0) != static_cast<ssize_t>(header.size()))
      throw OutputFileError("cannot write " + path + ": " + std::strerror(errno));
    write_whole(rest_path, rest);
    file->commit();
  }
};

}  // namespace

struct MeshExport::Impl {
  Impl(const Model& m, ExportPath p, double f, bool e) : model(m), path(std::move(p)), fps(f), error(e) {}
  const Model& model;
  ExportPath path;
  double fps;
  bool error;
  int frames = 0;
  int files = 0;                  // per-frame files named so far (OBJ, PLY, VTP)
  std::vector<std::string> file_list;  // their paths, in the order written
  std::vector<Pc2Stream> caches;  // PC2: the cloth, then each sphere
  std::vector<PvdEntry> index;    // PVD
  std::vector<std::string> named;  // PC2 and PVD once finished
  bool finished = false;

  const char* kind() const {
    return path.format == ExportFormat::Obj ? "OBJ" : path.format == ExportFormat::Ply ? "PLY" : "VTP";
  }

  // The per-frame files written that are still where they were written (the folder may have
  // been moved or removed while the run went on).
  std::vector<std::string> gone() const {
    std::vector<std::string> out;
    for (const std::string& f : file_list)
      if (::access(f.c_str(), F_OK) != 0) out.push_back(f);
    return out;
  }

  // A sequence (or a PVD's folder) complete: a longer earlier run's files of the same series
  // past this run's last frame would read as its continuation, and go (as --frames' PNGs do).
  // Only names of the series' exact form: PREFIX, the frame number, SUFFIX.
  void remove_later_frames() const {
    if (path.dir.empty()) return;
    std::error_code ec;
    std::vector<std::filesystem::path> later;
    const std::vector<std::string> prefixes = path.series_prefixes(model.num_spheres);
    for (const auto& entry : std::filesystem::directory_iterator(path.dir, ec)) {
      const std::string name = entry.path().filename().string();
      for (const std::string& prefix : prefixes) {
        if (name.size() <= prefix.size() + path.suffix.size() || name.rfind(prefix, 0) != 0 ||
            name.compare(name.size() - path.suffix.size(), path.suffix.size(), path.suffix) != 0)
          continue;
        const std::string number = name.substr(prefix.size(), name.size() - prefix.size() - path.suffix.size());
        const std::size_t width = static_cast<std::size_t>(path.digits);  // as %0Nd writes it: N digits, or more unpadded
        if (number.size() < width || number.size() > 9 || (number.size() > width && number[0] == '0') ||
            number.find_first_not_of("0123456789") != std::string::npos)
          continue;
        if (std::stol(number) >= frames) later.push_back(entry.path());
      }
    }
    for (const auto& p : later) std::filesystem::remove(p, ec);
  }

  std::string comment(const State& bodies) const {
    char text[96];
    std::snprintf(text, sizeof text, "clothsim %s t = %.17g s", model.name.c_str(), bodies.t);
    return text;
  }

  void add_part(int frame, int sphere, const MeshPart& part, const std::string& note) {
    if (path.format == ExportFormat::Pc2) {
      caches[static_cast<std::size_t>(sphere + 1)].add(part, note);
      return;
    }
    const std::string file = path.frame_file(frame, sphere);
    write_whole(file, path.format == ExportFormat::Obj   ? obj_text(part, note)
                      : path.format == ExportFormat::Ply ? ply_bytes(part, note)
                                                         : vtp_text(part));
    ++files;
    file_list.push_back(file);
    if (path.format == ExportFormat::Pvd) {
      // NAME/cloth_00000.vtp beside NAME.pvd: relative to the index, so the two move together.
      const std::filesystem::path dir_name = std::filesystem::path(path.dir).filename();
      index.push_back({static_cast<double>(frame) / fps, sphere + 1,
                       (dir_name / std::filesystem::path(file).filename()).string()});
    }
  }
};

MeshExport::MeshExport(const Model& model, ExportPath path, double fps, bool error)
    : impl_(std::make_unique<Impl>(model, std::move(path), fps, error)) {
  if (impl_->path.format == ExportFormat::Pc2) {
    const std::vector<std::string> files = impl_->path.final_files(model.num_spheres);
    for (std::size_t i = 0; i + 1 < files.size(); i += 2) impl_->caches.emplace_back(files[i], files[i + 1]);
  }
}

MeshExport::~MeshExport() = default;

void MeshExport::add(int frame, const State& bodies, const std::vector<float>* error) {
  Impl& m = *impl_;
  const std::string note = m.comment(bodies);
  if (!m.path.dir.empty() && m.frames == 0) {  // the per-frame files' directory, made at the first
    std::error_code ec;
    std::filesystem::create_directories(m.path.dir, ec);
    if (ec) throw ExportError("cannot create " + m.path.dir + ": " + ec.message());
  }
  try {
    m.add_part(frame, -1, cloth_part(m.model, bodies, m.error ? error : nullptr), note);
    for (int s = 0; s < m.model.num_spheres; ++s) m.add_part(frame, s, sphere_part(m.model, bodies, s), note);
  } catch (const OutputFileError& e) {
    throw ExportError(e.what());
  }
  m.frames = frame + 1;
}

void MeshExport::finish() {
  Impl& m = *impl_;
  // Never an index, nor a success, over files that are not there.
  const std::vector<std::string> gone = m.gone();
  if (!gone.empty())
    throw ExportError("cannot finish " + m.path.path + ": " + std::to_string(gone.size()) + " of the " +
                      std::to_string(m.files) + " " + m.kind() + " files written are gone (" + gone.front() +
                      " first): " + m.path.dir + " was moved or removed during the run");
  try {
    for (Pc2Stream& c : m.caches) {
      c.finish();
      m.named.push_back(c.path);
      m.named.push_back(c.rest_path);
    }
    if (m.path.format == ExportFormat::Pvd) {
      write_whole(m.path.path, pvd_text(m.index));
      m.named.push_back(m.path.path);
    }
  } catch (const OutputFileError& e) {
    throw ExportError(e.what());
  }
  m.remove_later_frames();
  m.finished = true;
}

std::vector<std::string> MeshExport::unwritten() const {
  const Impl& m = *impl_;
  if (m.finished) return {};
  return m.path.final_files(m.model.num_spheres);
}

int MeshExport::frames() const { return impl_->frames; }

std::vector<std::string> MeshExport::written_files() const {
  std::vector<std::string> out = impl_->file_list;
  out.insert(out.end(), impl_->named.begin(), impl_->named.end());
  return out;
}

std::string MeshExport::written() const {
  const Impl& m = *impl_;
  std::string out;
  for (const std::string& f : m.named) out += (out.empty() ? "" : ", ") + f;
  if (m.path.format == ExportFormat::Pc2 || m.files == 0) return out;
  const int here = m.files - static_cast<int>(m.gone().size());  // what the disk holds, not what was written
  if (here == 0) return out;
  return std::to_string(here) + " " + m.kind() + " files in " + m.path.dir + "/" + (out.empty() ? "" : ", " + out);
}

std::string MeshExport::lost() const {
  const Impl& m = *impl_;
  if (m.path.format == ExportFormat::Pc2 || m.files == 0) return "";
  const std::size_t gone = m.gone().size();
  if (gone == 0) return "";
  return std::to_string(gone) + " " + m.kind() + " files gone from " + m.path.dir +
         "/ (moved or removed during the run)";
}

}  // namespace clothsim
