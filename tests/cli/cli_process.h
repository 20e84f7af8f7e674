// Runs the built clothsim binary (CLOTHSIM_BINARY) as a user would, capturing exit code,
// stdout and stderr, for tests of the command-line contract.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
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

// `prefix` goes before the binary (e.g. "timeout --preserve-status -s INT 1").
inline CliResult run_clothsim(const std::vector<std::string>& args, const std::string& prefix = "") {
  namespace fs = std::filesystem;
  static int counter = 0;
  const fs::path dir = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / "cli_capture";
  fs::create_directories(dir);
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const std::string out = (dir / ("out_" + tag)).string(), err = (dir / ("err_" + tag)).string();
  std::string command = prefix.empty() ? "" : prefix + " ";
  command += shell_quote(CLOTHSIM_BINARY);
  for (const auto& a : args) command += " " + shell_quote(a);
  command += " >" + shell_quote(out) + " 2>" + shell_quote(err) + " </dev/null";
  const int status = std::system(command.c_str());
  CliResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = slurp(out);
  result.err = slurp(err);
  fs::remove(out);
  fs::remove(err);
  return result;
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
