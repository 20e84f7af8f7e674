#include "study_common.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <csignal>
#include <mutex>
#include <optional>

#include "clip/common/install_paths.h"
#include "clip/common/scene_options.h"
#include "scene/echo.h"

namespace clothsim::clip {
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

JsonObject bench_summary_keys(double duration, bool complete, const std::string& reference, double reference_dt,
                              double change_rms, bool converged) {
  JsonObject ref;
  ref.text("integrator", reference)
      .number("dt", reference_dt)
      .number("change_rms", change_rms)
      .number("estimated_error_m", change_rms)
      .boolean("converged", converged);
  JsonObject keys;
  keys.number("duration", duration).boolean("complete", complete).object("reference", ref);
  return keys;
}

struct SharedProgress::Impl {
  std::mutex mutex;
  Progress progress;
  Impl(std::string label, long total, std::string unit) : progress(std::move(label), total, std::move(unit)) {}
};

SharedProgress::SharedProgress(std::string label, long total, std::string unit)
    : impl_(std::make_shared<Impl>(std::move(label), total, std::move(unit))) {}

void SharedProgress::update(const analysis::StudyProgress& progress) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->progress.update(progress.done, progress.share());
}

std::function<void(const analysis::StudyProgress&)> SharedProgress::hook() {
  return [self = *this](const analysis::StudyProgress& p) mutable { self.update(p); };  // (shares impl_)
}

void SharedProgress::finish() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->progress.finish();
}

std::string tools_dir() {
  if (const char* env = std::getenv("CLOTHSIM_TOOLS_DIR"); env && *env) return env;
  const std::string installed = installed_data_dir();
  return installed.empty() ? std::string(CLOTHSIM_TOOLS_DIR) : installed + "/tools";
}

namespace {

constexpr int kChildFirstFd = 3;  // the descriptors handed to a plot script: its PNG, its CSV

// The child's side of run_process, between fork and exec: async-signal-safe calls only.
[[noreturn]] void exec_child(char* const* argv, pid_t parent, bool quiet, const std::vector<int>& fds) {
  ::setpgid(0, 0);                      // its own group: a Ctrl-C reaches us, and we end it
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // it never outlives us, even after our SIGKILL
  if (::getppid() != parent) ::_exit(127);  // we died before prctl took hold
  for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) ::signal(s, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  if (quiet) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
  }
  // Out of the way first (a source may itself be 3 or 4), then into place; dup2 clears
  // close-on-exec on the copy.
  int high[8];
  const std::size_t n = std::min<std::size_t>(fds.size(), 8);
  for (std::size_t i = 0; i < n; ++i) high[i] = ::fcntl(fds[i], F_DUPFD, 64);
  for (std::size_t i = 0; i < n; ++i) ::dup2(high[i], kChildFirstFd + static_cast<int>(i));
  ::execv(argv[0], argv);
  ::_exit(127);
}

// Runs argv (argv[0] a path), stdout and stderr to /dev/null when `quiet`, `fds` as the
// child's descriptors 3, 4...; returns the exit code, or -1 when stopped by a signal (the
// child's whole group killed and reaped first) or when it could not start.
int run_process(const std::vector<std::string>& args, bool quiet, const std::vector<int>& fds = {}) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) exec_child(argv.data(), parent, quiet, fds);
  ::setpgid(pid, pid);  // also here, so the kill below cannot race the child's own setpgid
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) return -1;
    if (interrupted()) {  // polled: the signal may have gone to any thread
      ::kill(-pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
      return -1;
    }
    ::usleep(10000);  // 10 ms: a signal is answered within that
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

PlotScript::PlotScript(std::string script, std::string png) : png_(std::move(png)) {
  script_ = (fs::path(tools_dir()) / script).string();
  require_writable_parent(png_, "--plot");
  // A device, FIFO or descriptor is streamed into whatever its name (docs/outputs.md).
  if (fs::path(png_).extension() != ".png" && !resolve_output(png_).streams)
    throw UsageError("--plot: " + png_ + " must end in .png");
  if (!fs::is_regular_file(script_))
    throw RuntimeFailure("--plot: plot script " + script_ + " not found (set CLOTHSIM_TOOLS_DIR to clothsim's tools/ directory)");
  // Debian's matplotlib is installed for the system python; a python3 earlier on PATH
  // (a virtualenv) may not see it, so /usr/bin/python3 is preferred.
  python_ = ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "";
  if (const char* env = std::getenv("CLOTHSIM_PYTHON"); env && *env) python_ = env;
  if (python_.empty()) throw RuntimeFailure("--plot needs python3 with matplotlib (apt-get install python3-matplotlib)");
  if (run_process({python_, "-c", "import matplotlib"}, true) != 0) {
    // A signal during the check kills the child: said as the stop it is, not a missing library.
    if (interrupted()) throw RuntimeFailure(std::string("stopped by ") + interrupt_signal_name() + "; nothing written");
    throw RuntimeFailure("--plot needs matplotlib for " + python_ + " (apt-get install python3-matplotlib)");
  }
}

void PlotScript::draw(const std::vector<std::string>& args) const { draw(args, -1, {}); }

void PlotScript::draw(const std::vector<std::string>& args, int csv_fd, const std::vector<std::string>& written) const {
  // The script writes into a nameless file of ours (or the device or pipe the PNG streams to)
  // through /dev/fd/3: killed at any moment, it leaves nothing under any name.
  std::optional<OutputFile> out;
  try {
    out.emplace(png_);
  } catch (const OutputFileError& e) {
    throw RuntimeFailure(e.what());
  }
  std::vector<std::string> argv{python_, script_};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.push_back("--out");
  argv.push_back("/dev/fd/" + std::to_string(kChildFirstFd));
  std::vector<int> fds{out->fd()};
  if (csv_fd >= 0) fds.push_back(csv_fd);
  const int code = run_process(argv, false, fds);
  if (interrupted()) {
    std::vector<std::string> kept;
    for (const std::string& path : written)
      if (!path.empty()) kept.push_back(path);
    throw RuntimeFailure(std::string("stopped by ") + interrupt_signal_name() + " while drawing the plot; " +
                         what_stays(kept, {png_}));
  }
  if (code != 0)
    throw RuntimeFailure("--plot: " + script_ + " failed (exit " + std::to_string(code) + "); no plot written");
  try {
    out->commit();
  } catch (const OutputFileError& e) {
    throw RuntimeFailure(e.what());
  }
}

void PlotScript::draw_from_csv(const std::string& csv,
                               const std::function<void(const std::string&)>& write_csv,
                               const std::vector<std::string>& args, const std::vector<std::string>& written) const {
  // Without --csv, the script reads a nameless CSV of ours through /proc/self/fd: nothing to
  // remove afterwards, nothing left by a kill.
  std::optional<OutputFile> temp;
  std::string source = csv;
  if (source.empty()) {
    try {
      temp.emplace(png_ + ".csv");
    } catch (const OutputFileError& e) {
      throw RuntimeFailure(e.what());
    }
    write_csv(temp->reopen_path());
    source = "/dev/fd/" + std::to_string(kChildFirstFd + 1);
  }
  std::vector<std::string> all{"--csv", source};
  all.insert(all.end(), args.begin(), args.end());
  draw(all, temp ? temp->fd() : -1, written);
  std::printf("plot: %s\n", png_.c_str());
}

std::string study_interrupted_message(std::size_t finished, std::size_t total, const std::string& unit,
                                      const std::vector<std::string>& kept, const std::string& plot) {
  std::vector<std::string> files;
  for (const std::string& path : kept)
    if (!path.empty()) files.push_back(finished < total ? path + " (incomplete)" : path);
  std::vector<std::string> not_written;
  if (!plot.empty()) not_written.push_back(plot);
  return std::string("stopped by ") + interrupt_signal_name() + ": " + std::to_string(finished) + " of " + std::to_string(total) + " " + unit + " finished; " +
         what_stays(files, not_written);
}

std::vector<double> parse_frame_dts(const std::string& text) {
  if (text == "none") return {};
  std::vector<double> out = parse_number_list(text, "--frame-dts");
  for (double dt : out)
    if (!(dt > 0.0)) throw UsageError("--frame-dts: " + csv_number(dt) + " is not a positive step (s)");
  return out;
}

std::unique_ptr<PlotScript> check_study_outputs(const std::string& scene, const std::string& csv,
                                                const std::string& summary, const std::string& plot,
                                                const std::string& plot_script) {
  refuse_clashing_paths({{scene, "the scene"}}, {{csv, "--csv"}, {plot, "--plot"}, {summary, "--summary"}});
  if (!csv.empty()) require_writable_parent(csv, "--csv");
  if (!summary.empty()) require_writable_parent(summary, "--summary");
  if (plot.empty()) return nullptr;
  return std::make_unique<PlotScript>(plot_script, plot);
}

}  // namespace clothsim::clip
