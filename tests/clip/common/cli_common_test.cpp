// Signals as every command answers them (cli_common.h, docs/outputs.md): SIGINT, SIGTERM and
// SIGHUP at any moment give 128 + N and one line of what stays; a plot script never
// outlives the command and leaves nothing; golden update writes all or none.
#include "clip/common/cli_common.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

namespace fs = std::filesystem;

std::string scene(const std::string& name) { return std::string(CLOTHSIM_SCENES_DIR) + "/" + name; }

// Running (a zombie no one reaps, as under a container's init, does not count).
bool process_exists(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return false;
  const std::size_t end = text.rfind(')');
  return end != std::string::npos && end + 2 < text.size() && text[end + 2] != 'Z';
}

TEST(Signals, SighupStopsARunWith129AndSaysWhatStays) {
  const std::string dir = scratch_dir("signals_hup");
  const StoppedResult r = run_clothsim_interrupted(
      {"run", scene("drape.yaml"), "--duration", "5", "--frames", dir + "/fr", "--metrics", dir + "/m.csv"}, 1.0,
      SIGHUP);
  EXPECT_EQ(r.exit_code, 129) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("stopped by SIGHUP at t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not written: " + dir + "/m.csv"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/m.csv"));
}

// imgdiff waits on a FIFO nobody writes: a command with nothing to poll is still answered.
// The program's 146 shared libraries take ld.so about 30 ms before any code of ours runs:
// build/clothsim is a static launcher that blocks SIGINT, SIGTERM and SIGHUP with its first
// instructions and execs the program, whose .preinit_array answers what is pending.
bool holds_signals_or_runs_the_program(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("SigBlk:", 0) == 0 && (std::stoull(line.substr(7), nullptr, 16) & 0x4003) == 0x4003) return true;
  std::error_code ec;
  const std::string exe = fs::read_symlink("/proc/" + std::to_string(pid) + "/exe", ec).string();
  return exe.size() >= 16 && exe.compare(exe.size() - 16, 16, "libexec/clothsim") == 0;
}

TEST(Signals, ASignalWithinAMillisecondOfExecIsAnsweredWithItsLine) {
  for (const int delay_us : {0, 0, 100, 300, 1000})
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
      const Capture capture;
      const pid_t pid = ::fork();
      if (pid == 0) {
        const int e = ::open(capture.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(e, 2);
        const std::string path = scene("drape.yaml");
        ::execl(CLOTHSIM_BINARY, CLOTHSIM_BINARY, "run", path.c_str(), "--duration", "5", static_cast<char*>(nullptr));
        ::_exit(127);
      }
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (!holds_signals_or_runs_the_program(pid) && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::microseconds(20));
      std::this_thread::sleep_for(std::chrono::microseconds(delay_us));
      ::kill(pid, signal);
      int status = 0;
      ::waitpid(pid, &status, 0);
      const CliResult r = capture.collect(status);
      EXPECT_EQ(r.exit_code, 128 + signal) << delay_us << " us: " << r.err;
      EXPECT_EQ(line_count(r.err), 1) << r.err;
      EXPECT_EQ(r.err.rfind(std::string("clothsim: stopped by ") + (signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP"), 0), 0u)
          << delay_us << " us: " << r.err;
    }
}

TEST(Signals, ACommandThatDoesNotPollEndsAtOnceSayingNothingWasWritten) {
  const std::string dir = scratch_dir("signals_no_poll");
  ASSERT_EQ(::mkfifo((dir + "/a.png").c_str(), 0600), 0);
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    const StoppedResult r =
        run_clothsim_interrupted({"imgdiff", dir + "/a.png", dir + "/a.png", "--diff", dir + "/d.png"}, 0.5, signal);
    EXPECT_EQ(r.exit_code, 128 + signal) << r.err;
    EXPECT_EQ(r.err, std::string("clothsim: stopped by ") + (signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP") +
                         "; nothing written\n");
    EXPECT_LT(r.seconds_to_exit, 1.0);
  }
  EXPECT_TRUE(only_files(dir, {"a.png"}));
}

// A stand-in for python3 that passes the matplotlib check, then records its pid and hangs as
// a slow plot would.
std::string hanging_python(const std::string& dir) {
  const std::string path = dir + "/python";
  std::ofstream(path) << "#!/bin/sh\n[ \"$1\" = -c ] && exit 0\necho $$ > " << dir << "/plot.pid\nexec sleep 30\n";
  fs::permissions(path, fs::perms::owner_all);
  return path;
}

pid_t plot_pid(const std::string& dir) {
  std::ifstream in(dir + "/plot.pid");
  pid_t pid = -1;
  in >> pid;
  return pid;
}

TEST(Signals, APlotScriptIsKilledAndReapedOnASignalAndLeavesNothing) {
  const std::string dir = scratch_dir("signals_plot");
  ::setenv("CLOTHSIM_PYTHON", hanging_python(dir).c_str(), 1);
  const StoppedResult r = run_clothsim_interrupted(
      {"bench", scene("spring.yaml"), "--dts", "0.01,0.005", "--duration", "1", "--plot", dir + "/wp.png"}, 3.0,
      SIGTERM);
  ::unsetenv("CLOTHSIM_PYTHON");
  EXPECT_EQ(r.exit_code, 143) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("stopped by SIGTERM while drawing the plot; nothing kept; not written: " + dir + "/wp.png"),
            std::string::npos)
      << r.err;
  EXPECT_LT(r.seconds_to_exit, 1.0);
  const pid_t child = plot_pid(dir);
  ASSERT_GT(child, 0) << "the plot had started";
  EXPECT_FALSE(process_exists(child)) << "the plot script outlived the command";
  EXPECT_TRUE(only_files(dir, {"python", "plot.pid"}));
}

TEST(Signals, AStopWhileDrawingThePlotNamesTheCsvAndSummaryKept) {
  const std::string dir = scratch_dir("signals_plot_kept");
  ::setenv("CLOTHSIM_PYTHON", hanging_python(dir).c_str(), 1);
  const StoppedResult r = run_clothsim_interrupted({"bench", scene("spring.yaml"), "--dts", "0.01,0.005", "--duration",
                                                    "1", "--csv", dir + "/wp.csv", "--summary", dir + "/wp.json",
                                                    "--plot", dir + "/wp.png"},
                                                   3.0, SIGINT);
  ::unsetenv("CLOTHSIM_PYTHON");
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("stopped by SIGINT while drawing the plot; kept " + dir + "/wp.csv, " + dir +
                       "/wp.json; not written: " + dir + "/wp.png"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(dir + "/wp.csv"));
  EXPECT_TRUE(fs::exists(dir + "/wp.json"));
}

TEST(Signals, APlotScriptDiesWithACommandKilledBySigkill) {
  const std::string dir = scratch_dir("signals_plot_kill");
  ::setenv("CLOTHSIM_PYTHON", hanging_python(dir).c_str(), 1);
  const StoppedResult r = run_clothsim_interrupted(
      {"bench", scene("spring.yaml"), "--dts", "0.01,0.005", "--duration", "1", "--plot", dir + "/wp.png"}, 3.0,
      SIGKILL);
  ::unsetenv("CLOTHSIM_PYTHON");
  EXPECT_EQ(r.exit_code, 128 + SIGKILL);
  const pid_t child = plot_pid(dir);
  ASSERT_GT(child, 0) << "the plot had started";
  for (int i = 0; i < 100 && process_exists(child); ++i) ::usleep(10000);
  EXPECT_FALSE(process_exists(child)) << "PR_SET_PDEATHSIG";
  EXPECT_TRUE(only_files(dir, {"python", "plot.pid"}));
}

TEST(Signals, GoldenUpdateStoppedChangesNoGoldenImage) {
  const std::string dir = scratch_dir("signals_golden");
  fs::copy_file(scene("drape.yaml"), dir + "/d.yaml");
  // dt 1e-5: about 5 s of work on an idle machine, so the signal at 1 s lands inside it.
  std::ofstream(dir + "/m.yaml") << "size: [160, 90]\ngoldens:\n  - {scene: d.yaml, times: [0.05, 4], dt: 1.0e-5}\n";
  const StoppedResult r = run_clothsim_interrupted({"golden", "update", dir + "/m.yaml"}, 1.0, SIGTERM);
  EXPECT_EQ(r.exit_code, 143) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("stopped by SIGTERM at t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not written: every golden image (update writes all or none)"), std::string::npos) << r.err;
  EXPECT_TRUE(only_files(dir, {"d.yaml", "m.yaml"})) << "the image at 0.05 s, made before the signal, is not named";
}

}  // namespace
}  // namespace clothsim::testing

namespace clothsim::testing {
namespace {

namespace fs = std::filesystem;

// Clashing paths (refuse_clashing_paths, docs/outputs.md "An output never replaces an input").
struct ClashFolder {
  // The test's own name: ctest runs each test in its own process, several at once, so a
  // per-process counter alone would hand two of them the same folder.
  std::string dir = scratch_dir("clash_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                                "_" + std::to_string(counter++));
  std::string scene_text;
  ClashFolder() {
    fs::copy_file(std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml", dir + "/s.yaml");
    scene_text = slurp(dir + "/s.yaml");
  }
  static inline int counter = 0;
};

TEST(ClashingPaths, AnOutputThatIsTheSceneUnderAnySpellingIsRefusedAndTheSceneKept) {
  ClashFolder f;
  fs::create_symlink("s.yaml", f.dir + "/link.yaml");
  fs::create_hard_link(f.dir + "/s.yaml", f.dir + "/hard.yaml");
  fs::create_directories(f.dir + "/sub");
  for (const std::string& spelling : {f.dir + "/s.yaml", f.dir + "/./s.yaml", f.dir + "/sub/../s.yaml",
                                      f.dir + "/link.yaml", f.dir + "/hard.yaml"})
    for (const char* option : {"--metrics", "--state", "--summary"}) {
      const CliResult r = run_clothsim({"run", f.dir + "/s.yaml", "--duration", "0.1", option, spelling});
      EXPECT_EQ(r.exit_code, 2) << option << " " << spelling;
      EXPECT_EQ(line_count(r.err), 1) << r.err;
      EXPECT_NE(r.err.find(option + std::string(" ") + spelling + " is the scene " + f.dir + "/s.yaml"),
                std::string::npos)
          << r.err;
      EXPECT_EQ(slurp(f.dir + "/s.yaml"), f.scene_text);
    }
}

TEST(ClashingPaths, TwoOutputsAtOneFileByAnotherNameAreRefusedBeforeAnyWork) {
  ClashFolder f;
  fs::create_symlink("x.csv", f.dir + "/dangling.csv");  // x.csv does not exist yet
  const CliResult r = run_clothsim({"run", f.dir + "/s.yaml", "--duration", "0.1", "--metrics", f.dir + "/x.csv",
                                    "--state", f.dir + "/dangling.csv"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--state and --metrics both write " + f.dir + "/dangling.csv"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(f.dir + "/x.csv"));
}

TEST(ClashingPaths, AStillAmongTheFramesIsRefused) {
  ClashFolder f;
  const CliResult r = run_clothsim({"run", f.dir + "/s.yaml", "--duration", "0.1", "--frames", f.dir + "/fr", "--still",
                                    "0.1", "-o", f.dir + "/fr/../fr/frame_00001.png"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--frames " + f.dir + "/fr would write frames over -o/--output"), std::string::npos) << r.err;
}

// --export's files are outputs too: a PC2's rest mesh named as --state, or a sequence over the
// frames another output writes, is refused before any work (run and compare alike).
TEST(ClashingPaths, ExportFilesClashWithTheOtherOutputs) {
  ClashFolder f;
  const CliResult pc2 = run_clothsim({"run", f.dir + "/s.yaml", "--duration", "0.1", "--export", f.dir + "/c.pc2",
                                      "--state", f.dir + "/./c.obj"});
  EXPECT_EQ(pc2.exit_code, 2) << pc2.err;
  EXPECT_EQ(line_count(pc2.err), 1) << pc2.err;
  EXPECT_FALSE(fs::exists(f.dir + "/c.pc2"));
  const CliResult series = run_clothsim({"compare", f.dir + "/s.yaml", "--duration", "0.1", "--integrators", "rk4",
                                         "--export", f.dir + "/e/frame_%05d.obj", "--summary",
                                         f.dir + "/e/rk4/frame_00001.obj"});
  EXPECT_EQ(series.exit_code, 2) << series.err;
  EXPECT_EQ(slurp(f.dir + "/s.yaml"), f.scene_text);
}

// A per-frame name made into a link to the scene (the probe's case: ln -s ../drape.yaml
// out/frame_00000.obj) is refused before any work, for every per-frame output of run and
// compare: OBJ and PLY series, a PVD's VTPs and --frames PNGs; the scene is never touched.
TEST(ClashingPaths, APerFrameNameLinkedToTheSceneIsRefusedAndTheSceneKept) {
  struct Case {
    std::vector<std::string> args;
    std::string link;  // relative to the folder
  };
  const std::vector<Case> cases = {
      {{"run", "@/s.yaml", "--export", "@/o/frame_%05d.obj"}, "o/frame_00000.obj"},
      {{"run", "@/s.yaml", "--export", "@/o/frame_%05d.ply"}, "o/frame_00002.ply"},
      {{"run", "@/s.yaml", "--export", "@/v.pvd"}, "v/cloth_00001.vtp"},
      {{"run", "@/s.yaml", "--frames", "@/fr"}, "fr/frame_00000.png"},
      {{"compare", "@/s.yaml", "--integrators", "rk4,midpoint", "--frames", "@/fr"}, "fr/rk4/frame_00000.png"},
      {{"compare", "@/s.yaml", "--integrators", "rk4,midpoint", "--export", "@/o/frame_%05d.obj"},
       "o/midpoint/frame_00001.obj"},
  };
  for (const bool hard : {false, true})
    for (const Case& c : cases) {
      ClashFolder f;
      const fs::path link = fs::path(f.dir) / c.link;
      fs::create_directories(link.parent_path());
      if (hard) fs::create_hard_link(f.dir + "/s.yaml", link);
      else fs::create_symlink(fs::relative(f.dir + "/s.yaml", link.parent_path()), link);
      std::vector<std::string> args;
      for (const std::string& a : c.args) args.push_back(a[0] == '@' ? f.dir + a.substr(1) : a);
      args.insert(args.end(), {"--duration", "0.1"});
      const CliResult r = run_clothsim(args);
      EXPECT_EQ(r.exit_code, 2) << c.link << (hard ? " (hard)" : "") << ": " << r.err;
      EXPECT_EQ(line_count(r.err), 1) << r.err;
      EXPECT_NE(r.err.find("a link to the scene"), std::string::npos) << r.err;
      EXPECT_EQ(slurp(f.dir + "/s.yaml"), f.scene_text) << c.link;
    }
}

// An output onto a name a PVD's series claims is another output's file.
TEST(ClashingPaths, AnOutputAmongAPvdsFilesIsRefused) {
  ClashFolder f;
  const CliResult r = run_clothsim({"run", f.dir + "/s.yaml", "--duration", "0.1", "--export", f.dir + "/v.pvd",
                                    "--metrics", f.dir + "/v/cloth_00000.vtp"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_FALSE(fs::exists(f.dir + "/v.pvd"));
}

TEST(ClashingPaths, DevicesAreNeverCompared) {
  ClashFolder f;
  const CliResult r = run_clothsim({"run", f.dir + "/s.yaml", "--duration", "0.1", "--metrics", "/dev/null", "--state",
                                    "/dev/null", "--summary", "/dev/null"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(ClashingPaths, EveryStudyRefusesAnOutputOntoItsScene) {
  ClashFolder f;
  fs::create_symlink(f.dir + "/s.yaml", f.dir + "/abs.yaml");
  for (const std::string study : {"bench", "stability", "converge"})
    for (const std::string option : {"--csv", "--summary", "--plot"}) {
      const CliResult r = run_clothsim({study, f.dir + "/s.yaml", option, f.dir + "/abs.yaml"});
      EXPECT_EQ(r.exit_code, 2) << study << " " << option;
      EXPECT_NE(r.err.find("an output never replaces an input"), std::string::npos) << r.err;
    }
  EXPECT_EQ(slurp(f.dir + "/s.yaml"), f.scene_text);
}

}  // namespace
}  // namespace clothsim::testing
