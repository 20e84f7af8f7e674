#include "install_paths.h"

#include <dlfcn.h>

#include <filesystem>
#include <system_error>

namespace clothsim::clip {

namespace fs = std::filesystem;

namespace {
// PREFIX for a program at PREFIX/libexec/clothsim/clothsim or a module at
// PREFIX/lib/python3*/dist-packages/clothsim*.so; empty for anything else.
fs::path prefix_of(const fs::path& self) {
  const fs::path dir = self.parent_path();
  if (dir.filename() == "clothsim" && dir.parent_path().filename() == "libexec") return dir.parent_path().parent_path();
  if (dir.filename() == "dist-packages" || dir.filename() == "site-packages") {
    const fs::path lib = dir.parent_path().parent_path();
    if (lib.filename() == "lib") return lib.parent_path();
  }
  return {};
}
}  // namespace

std::string installed_data_dir() {
  // The program is /proc/self/exe; the Python module is the shared object this code was
  // loaded from (dladdr: for the main program glibc names argv[0], the launcher's path, so
  // it is asked second).
  std::error_code ec;
  fs::path prefix = prefix_of(fs::canonical("/proc/self/exe", ec));
  Dl_info info{};
  if (prefix.empty() && ::dladdr(reinterpret_cast<void*>(&installed_data_dir), &info) != 0 && info.dli_fname &&
      *info.dli_fname) {
    const fs::path self = fs::canonical(info.dli_fname, ec);
    if (!ec) prefix = prefix_of(self);
  }
  if (prefix.empty()) return "";
  const fs::path data = prefix / "share" / "clothsim";
  return fs::is_directory(data, ec) ? data.string() : "";
}

std::string shipped_scenes_dir() {
  const std::string installed = installed_data_dir();
  return installed.empty() ? std::string(CLOTHSIM_SOURCE_SCENES_DIR) : installed + "/scenes";
}

std::string resolve_scene_argument(const std::string& arg) {
  std::error_code ec;
  if (arg.empty() || arg == "-" || fs::exists(arg, ec) || arg.find('/') != std::string::npos) return arg;
  const fs::path name = fs::path(arg).extension() == ".yaml" ? fs::path(arg) : fs::path(arg + ".yaml");
  const fs::path shipped = fs::path(shipped_scenes_dir()) / name;
  return fs::is_regular_file(shipped, ec) ? shipped.string() : arg;
}

}  // namespace clothsim::clip
