// Runs the built clothsim binary (CLOTHSIM_BINARY) as a user would, capturing exit code,
// stdout and stderr, for tests of the command-line contract.
#pragma once

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace clothsim::testing {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

inline std::string shell_quote(const std::string& arg) {
  std::string q = "'";
  for (char c : arg) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Where one run's stdout and stderr are captured, and collecting them into a CliResult
// (the files are removed) once the process has ended with wait status `status`.
struct Capture {
  std::string out, err;
  Capture() {
    namespace fs = std::filesystem;
    static int counter = 0;
    const fs::path dir = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / "cli_capture";
    fs::create_directories(dir);
    const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
    out = (dir / ("out_" + tag)).string();
    err = (dir / ("err_" + tag)).string();
  }
  CliResult collect(int status) const {
    CliResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = slurp(out);
    result.err = slurp(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return result;
  }
};

inline CliResult run_clothsim(const std::vector<std::string>& args, const std::string& prefix = "") {
  const Capture capture;
  std::string command = prefix.empty() ? "" : prefix + " ";
  command += shell_quote(CLOTHSIM_BINARY);
  for (const auto& a : args) command += " " + shell_quote(a);
  command += " >" + shell_quote(capture.out) + " 2>" + shell_quote(capture.err) + " </dev/null";
  return capture.collect(std::system(command.c_str()));
}

// Any program (a reader of clothsim's outputs: python3, ffprobe), as run_clothsim runs clothsim.
inline CliResult run_process(const std::vector<std::string>& argv) {
  const Capture capture;
  std::string command;
  for (const auto& a : argv) command += (command.empty() ? "" : " ") + shell_quote(a);
  command += " >" + shell_quote(capture.out) + " 2>" + shell_quote(capture.err) + " </dev/null";
  return capture.collect(std::system(command.c_str()));
}

// A run stopped by a signal, and how long it took to exit once the signal was sent.
struct StoppedResult : CliResult {
  double seconds_to_exit = 0.0;
};

// Starts clothsim, sends it one `signal` after `seconds` (as Ctrl-C in a terminal does: once,
// to the process; `timeout -s INT` would also signal its whole process group, and a second
// signal kills by design), and waits for it.
inline StoppedResult run_clothsim_signalled(const std::vector<std::string>& args, double seconds,
                                            const std::vector<int>& signals);
inline StoppedResult run_clothsim_interrupted(const std::vector<std::string>& args, double seconds,
                                              int signal = SIGINT) {
  return run_clothsim_signalled(args, seconds, {signal});
}

// Same, sending each of `signals` in turn, at once (SIGSTOP first and SIGCONT last make the
// ones between arrive together), when `ready` says so (it is asked every 10 ms).
inline StoppedResult run_clothsim_signalled_when(const std::vector<std::string>& args,
                                                 const std::function<bool()>& ready,
                                                 const std::vector<int>& signals) {
  const Capture capture;
  std::vector<std::string> argv_strings = {CLOTHSIM_BINARY};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_strings) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int o = ::open(capture.out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(capture.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(o, 1);
    ::dup2(e, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  while (!ready()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto sent = std::chrono::steady_clock::now();
  for (const int signal : signals) ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  StoppedResult result;
  static_cast<CliResult&>(result) = capture.collect(status);
  result.seconds_to_exit = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  return result;
}

inline StoppedResult run_clothsim_signalled(const std::vector<std::string>& args, double seconds,
                                            const std::vector<int>& signals) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  return run_clothsim_signalled_when(args, [until] { return std::chrono::steady_clock::now() >= until; }, signals);
}

// Interrupted once `path` exists (an output written by rename is then whole), or after
// `give_up` seconds: a test of what a run keeps must not depend on how loaded the machine is.
inline StoppedResult run_clothsim_interrupted_after_file(const std::vector<std::string>& args,
                                                         const std::string& path, int signal,
                                                         double give_up = 120.0) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(give_up);
  return run_clothsim_signalled_when(
      args, [&] { return std::filesystem::exists(path) || std::chrono::steady_clock::now() >= until; }, {signal});
}

// Number of lines in `text` (a message must be one line).
inline int line_count(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n + (!text.empty() && text.back() != '\n');
}

// A fresh, empty scratch directory under the test output directory.
inline std::string scratch_dir(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

// True when `dir` holds nothing but the listed file names (no temporaries left behind).
inline bool only_files(const std::string& dir, const std::vector<std::string>& names) {
  namespace fs = std::filesystem;
  std::size_t seen = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    bool listed = false;
    for (const auto& n : names) listed = listed || n == name;
    if (!listed) return false;
    ++seen;
  }
  return seen == names.size();
}

}  // namespace clothsim::testing
