// Where a run's outputs go (docs/outputs.md): a device, FIFO or descriptor is written through,
// never replaced; a symlink is followed. As root (containers, CI) a replaced /dev/null would
// break the machine, so those cases run in a private mount namespace over a scratch /dev.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

namespace fs = std::filesystem;

std::string spring() { return std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml"; }

std::string shell_output(const std::string& command) {
  std::string out;
  if (std::FILE* pipe = ::popen(command.c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, pipe)) out += buf;
    ::pclose(pipe);
  }
  return out;
}

bool is_character_device(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

TEST(RunOutputs, MetricsToDevNullLeavesACharacterDevice) {
  const std::string run = shell_quote(CLOTHSIM_BINARY) + " run " + shell_quote(spring()) +
                          " --duration 0.1 --metrics /dev/null --state /dev/null --summary /dev/null";
  if (::geteuid() == 0) {
    // root could replace the real /dev/null: a tmpfs over /dev seen by this command only.
    const std::string script = "mount -t tmpfs none /dev && mknod -m 666 /dev/null c 1 3 && " + run +
                               " >/dev/null 2>&1 && test -c /dev/null && echo still-a-device";
    EXPECT_EQ(shell_output("unshare -m sh -c " + shell_quote(script) + " 2>&1"), "still-a-device\n");
    // And as an unprivileged user, who cannot write /dev itself.
    const CliResult nobody = run_clothsim({"run", spring(), "--duration", "0.1", "--metrics", "/dev/null"},
                                          "setpriv --reuid=nobody --regid=nogroup --clear-groups");
    EXPECT_EQ(nobody.exit_code, 0) << nobody.err;
  } else {
    const CliResult r = run_clothsim({"run", spring(), "--duration", "0.1", "--metrics", "/dev/null"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_TRUE(is_character_device("/dev/null"));
}

TEST(RunOutputs, StillToStdoutStreamsAPngAndSaysTheRestOnStderr) {
  for (const char* out : {"/dev/stdout", "-"}) {
    const CliResult r = run_clothsim({"run", spring(), "--still", "0.1", "-o", out});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << out;
    EXPECT_NE(r.err.find("spring"), std::string::npos) << "the summary goes to stderr";
  }
}

TEST(RunOutputs, StillIntoAFifoStreamsAndKeepsTheFifo) {
  const std::string dir = scratch_dir("run_outputs_fifo");
  const std::string fifo = dir + "/pipe.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const CliResult r = run_clothsim({"run", spring(), "--still", "0.1", "-o", fifo},
                                   "cat " + shell_quote(fifo) + " > " + shell_quote(dir + "/got.png") + " &");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

TEST(RunOutputs, MetricsThroughASymlinkReplaceItsTargetAndKeepTheLink) {
  const std::string dir = scratch_dir("run_outputs_symlink");
  { std::ofstream(dir + "/real.csv") << "old\n"; }
  fs::create_symlink("real.csv", dir + "/m.csv");
  const CliResult r = run_clothsim({"run", spring(), "--duration", "0.1", "--metrics", dir + "/m.csv"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir + "/m.csv"));
  EXPECT_EQ(slurp(dir + "/real.csv").rfind("step,t,", 0), 0u);
  EXPECT_TRUE(only_files(dir, {"m.csv", "real.csv"}));
}

// A file-size limit stops the state (the largest file) after the metrics and summary were
// written: the one line says so, rather than only "cannot write s.csv".
TEST(RunOutputs, AWriteFailureNamesTheFilesKeptAndNotWritten) {
  const std::string dir = scratch_dir("run_outputs_ulimit");
  const CliResult r = run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--duration", "0.1",
                                    "--state", dir + "/s.csv", "--metrics", dir + "/m.csv", "--summary", dir + "/s.json"},
                                   "ulimit -f 50;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("cannot write " + dir + "/s.csv: File too large; kept " + dir + "/m.csv, " + dir +
                       "/s.json; not written: " + dir + "/s.csv"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(only_files(dir, {"m.csv", "s.json"}));
}

}  // namespace
}  // namespace clothsim::testing
