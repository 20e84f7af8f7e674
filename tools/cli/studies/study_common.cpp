#include "study_common.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "cli/common/scene_options.h"
#include "scene/echo.h"

extern char** environ;

namespace clothsim::cli {
namespace fs = std::filesystem;

std::vector<double> parse_number_list(const std::string& text, const std::string& option) {
  const std::vector<std::string> items = split_list(text);
  if (items.empty()) throw UsageError(option + ": empty list (expected numbers separated by commas)");
  std::vector<double> values;
  for (const std::string& item : items) {
    if (item.empty()) throw UsageError(option + ": empty item in " + in_quotes(text));
    const std::optional<double> v = parse_number_or_fraction(item);
    if (!v) throw UsageError(option + ": " + in_quotes(item) + " is not a finite number (or a fraction like 1/60)");
    values.push_back(*v);
  }
  return values;
}

std::string csv_number(double value) {
  if (std::isnan(value)) return "nan";
  // The shortest of %.15g, %.16g, %.17g that reads back to the same double: 0.005 stays
  // "0.005", and no value loses a bit.
  char buf[40];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  return buf;
}

std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return quoted + "\"";
}

struct SharedProgress::Impl {
  std::mutex mutex;
  Progress progress;
  Impl(std::string label, long total, std::string unit) : progress(std::move(label), total, std::move(unit)) {}
};

SharedProgress::SharedProgress(std::string label, long total, std::string unit)
    : impl_(std::make_shared<Impl>(std::move(label), total, std::move(unit))) {}

void SharedProgress::update(long done, long /*total*/) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->progress.update(done);
}

void SharedProgress::finish() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->progress.finish();
}

std::string tools_dir() {
  if (const char* env = std::getenv("CLOTHSIM_TOOLS_DIR"); env && *env) return env;
  return CLOTHSIM_TOOLS_DIR;
}

namespace {

// Runs argv (argv[0] a path), stdout to /dev/null unless `quiet` is false; returns the exit code.
int run_process(const std::vector<std::string>& args, bool quiet) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

PlotScript::PlotScript(std::string script, std::string png) : png_(std::move(png)) {
  script_ = (fs::path(tools_dir()) / script).string();
  require_writable_parent(png_, "--plot");
  if (fs::path(png_).extension() != ".png") throw UsageError("--plot: " + png_ + " must end in .png");
  if (!fs::is_regular_file(script_))
    throw RuntimeFailure("--plot: plot script " + script_ + " not found (set CLOTHSIM_TOOLS_DIR to clothsim's tools/ directory)");
  // Debian's matplotlib is installed for the system python; a python3 earlier on PATH
  // (a virtualenv) may not see it, so /usr/bin/python3 is preferred.
  python_ = ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "";
  if (const char* env = std::getenv("CLOTHSIM_PYTHON"); env && *env) python_ = env;
  if (python_.empty()) throw RuntimeFailure("--plot needs python3 with matplotlib (apt-get install python3-matplotlib)");
  if (run_process({python_, "-c", "import matplotlib"}, true) != 0)
    throw RuntimeFailure("--plot needs matplotlib for " + python_ + " (apt-get install python3-matplotlib)");
}

void PlotScript::draw(const std::vector<std::string>& args) const {
  const std::string temp = temp_path_beside(png_);
  std::vector<std::string> argv{python_, script_};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.push_back("--out");
  argv.push_back(temp);
  const int code = run_process(argv, false);
  if (code != 0) {
    std::remove(temp.c_str());
    throw RuntimeFailure("--plot: " + script_ + " failed (exit " + std::to_string(code) + "); no plot written");
  }
  if (std::rename(temp.c_str(), png_.c_str()) != 0) {
    std::remove(temp.c_str());
    throw RuntimeFailure("cannot rename " + temp + " to " + png_ + ": " + std::strerror(errno));
  }
}

void PlotScript::draw_from_csv(const std::string& csv,
                               const std::function<void(const std::string&)>& write_csv,
                               const std::vector<std::string>& args) const {
  struct RemoveOnExit {  // the temporary CSV goes whether the script succeeds or throws
    std::string path;
    ~RemoveOnExit() {
      if (!path.empty()) std::remove(path.c_str());
    }
  } temp;
  std::string source = csv;
  if (source.empty()) {
    temp.path = temp_path_beside(png_ + ".csv");
    write_csv(temp.path);
    source = temp.path;
  }
  std::vector<std::string> all{"--csv", source};
  all.insert(all.end(), args.begin(), args.end());
  draw(all);
  std::printf("plot: %s\n", png_.c_str());
}

std::string study_interrupted_message(std::size_t finished, std::size_t total, const std::string& unit,
                                      const std::vector<std::string>& kept, const std::string& plot) {
  std::vector<std::string> files;
  for (const std::string& path : kept)
    if (!path.empty()) files.push_back(finished < total ? path + " (incomplete)" : path);
  std::vector<std::string> not_written;
  if (!plot.empty()) not_written.push_back(plot);
  return "interrupted: " + std::to_string(finished) + " of " + std::to_string(total) + " " + unit + " finished; " +
         what_stays(files, not_written);
}

std::vector<double> parse_frame_dts(const std::string& text) {
  if (text == "none") return {};
  std::vector<double> out = parse_number_list(text, "--frame-dts");
  for (double dt : out)
    if (!(dt > 0.0)) throw UsageError("--frame-dts: " + csv_number(dt) + " is not a positive step (s)");
  return out;
}

}  // namespace clothsim::cli
