// `clothsim run` and `clothsim validate` as users call them: outputs, exit codes, and every
// bad input of the engine issue answered by one line naming file/line/key, with nothing
// left on disk.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include "core/integrators/integrator_kind.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli/cli_process.h"
#include "cli/run_reports.h"
#include "render/png_io.h"

namespace clothsim::testing {
namespace {
namespace fs = std::filesystem;

std::string shipped(const std::string& name) { return std::string(CLOTHSIM_SCENES_DIR) + "/" + name; }

std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

int rows(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST(CmdRun, WritesMetricsPerFrameAndTheFinalStateAtFullPrecision) {
  const std::string dir = scratch_dir("run_outputs");
  const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--duration", "1", "--metrics",
                                    dir + "/m.csv", "--state", dir + "/s.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("symplectic_euler"), std::string::npos);
  std::ifstream metrics(dir + "/m.csv");
  std::string header;
  std::getline(metrics, header);
  EXPECT_EQ(header.rfind("step,t,kinetic,spring_potential,gravity_potential,total_energy,max_strain,"
                         "contacts,force_evals", 0), 0u);
  EXPECT_EQ(rows(dir + "/m.csv"), 1 + 31);  // header + frames at 0, 1/30, ..., 1 s
  std::ifstream state(dir + "/s.csv");
  std::string line;
  std::getline(state, line);
  EXPECT_EQ(line, "id,x,y,z,vx,vy,vz");
  EXPECT_EQ(rows(dir + "/s.csv"), 1 + 2);
  EXPECT_TRUE(only_files(dir, {"m.csv", "s.csv"}));
}

TEST(CmdRun, TwoOutputsAtOnePathAreAUsageErrorBeforeAnyWork) {
  // Each would overwrite the other; the second spelling of the path (./, a directory and ..)
  // is the same file.
  const std::string dir = scratch_dir("run_shared_output");
  fs::create_directories(dir + "/sub");
  const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.1", "--metrics", dir + "/m.csv",
                                    "--summary", dir + "/sub/../m.csv"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--summary and --metrics both write "), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/m.csv"));
  const CliResult c = run_clothsim({"compare", shipped("spring.yaml"), "--duration", "0.1", "--width", "320", "--height",
                                    "180", "--still", "0.1", "-o", dir + "/x.png", "--sheet", dir + "/./x.png",
                                    "--times", "0.1"});
  EXPECT_EQ(c.exit_code, 2) << c.err;
  EXPECT_NE(c.err.find("both write"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(dir + "/x.png"));
}

TEST(CmdRun, AnEmptyIterationsIsRefusedNotIgnored) {
  // `--iterations ''` ran the scene's own settings, exit 0, as if the option were not given.
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--integrator", "vbd", "--duration", "0.05",
                                    "--iterations", ""});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--iterations"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(CmdRun, MetricsHaveOneRowPerStepWhereAStepIsLongerThanAFrame) {
  // 0.1 s steps, frames at 30 Hz: the run stands on each state for three frames; one row each.
  const std::string dir = scratch_dir("run_metrics_long_steps");
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--integrator", "implicit_euler", "--dt", "0.1",
                                    "--duration", "0.5", "--metrics", dir + "/m.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(rows(dir + "/m.csv"), 1 + 6);  // header + steps 0 .. 5
}

TEST(CmdRun, SameSceneTwiceGivesIdenticalStateFiles) {
  const std::string dir = scratch_dir("run_twice");
  for (const char* name : {"a.csv", "b.csv"})
    ASSERT_EQ(run_clothsim({"run", shipped("chain.yaml"), "--duration", "0.2", "--state", dir + "/" + name}).exit_code, 0);
  EXPECT_EQ(slurp(dir + "/a.csv"), slurp(dir + "/b.csv"));
}

TEST(CmdRun, OptionsOverrideTheScene) {
  const std::string dir = scratch_dir("run_options");
  const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--integrator", "explicit_euler",
                                    "--dt", "0.002", "--duration", "0.5", "--set",
                                    "cloth.springs.structural.stiffness=400"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("explicit_euler, dt = 0.002 s, 250 steps"), std::string::npos) << r.out;
  const CliResult per_frame = run_clothsim({"run", shipped("spring.yaml"), "--dt", "1/60", "--duration", "0.5"});
  ASSERT_EQ(per_frame.exit_code, 0) << per_frame.err;
  EXPECT_NE(per_frame.out.find("dt = 0.0166667 s, 30 steps"), std::string::npos) << "one step per frame, as a fraction\n"
                                                                                   << per_frame.out;
}

TEST(CmdRun, DivergenceExitsThreeSayingWhenAndKeepsMetricsButNoState) {
  const std::string dir = scratch_dir("run_diverged");
  const CliResult r = run_clothsim({"run", shipped("stiff.yaml"), "--integrator", "explicit_euler",
                                    "--metrics", dir + "/m.csv", "--state", dir + "/s.csv"});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("stiff.yaml: diverged at step"), std::string::npos) << r.err;
  EXPECT_TRUE(only_files(dir, {"m.csv"}));
}

TEST(CmdRun, AColourScaleWithNothingMeasuredSaysTheRunDivergedFirstNotThatTheClothIsAtRest) {
  // RK4 at 0.01 s blows the drape up at t = 0.03 s, before the first frame after t = 0: its
  // only error measured is the start's, 0. The message said "the first second is at rest".
  const std::string dir = scratch_dir("run_scale_diverged");
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--integrator", "rk4", "--dt", "0.01", "--color",
                                    "error", "--duration", "1", "--still", "0.5", "-o", dir + "/still.png"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("run: colour scale for error: 1e-06 to 0.001 m, a default: the run diverged at t = 0.03 s "
                       "before any error above 0 was measured"),
            std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("at rest"), std::string::npos) << r.err;
}

TEST(CmdRun, EveryRegisteredIntegratorIsInTheHelpAndRunsByItsName) {
  const CliResult help = run_clothsim({"--help"});
  ASSERT_EQ(help.exit_code, 0);
  const CliResult run_help = run_clothsim({"run", "--help"});
  const CliResult compare_help = run_clothsim({"compare", "--help"});
  for (const IntegratorInfo& info : integrator_registry()) {
    const std::string name(info.name);
    EXPECT_NE(help.out.find(name + " "), std::string::npos) << name << "\n" << help.out;
    EXPECT_NE(help.out.find(std::string(info.description)), std::string::npos) << name;
    EXPECT_NE(run_help.out.find(name), std::string::npos) << name;
    EXPECT_NE(compare_help.out.find(std::string(info.description)), std::string::npos) << name;
    const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--integrator", name, "--duration", "0.01"});
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_NE(r.out.find(name), std::string::npos) << r.out;
  }
}

TEST(CmdRun, StrictExitsFourWhenAnImplicitStepDidNotConvergeAndStillWritesItsOutputs) {
  // One Newton iteration cannot meet a 1e-12 tolerance on the stiff cloth in contact.
  const std::string dir = scratch_dir("run_strict");
  const std::vector<std::string> args{"run", shipped("stiff.yaml"), "--duration", "0.3", "--set",
                                      "implicit.newton_max_iterations=1", "--set",
                                      "implicit.newton_tolerance=1e-12", "--state", dir + "/s.csv"};
  std::vector<std::string> strict = args;
  strict.push_back("--strict");
  const CliResult r = run_clothsim(strict);
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--strict:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("did not converge"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("steps not converged"), std::string::npos) << r.out;
  EXPECT_TRUE(only_files(dir, {"s.csv"}));
  // Without --strict the same run succeeds, the count in its summary.
  EXPECT_EQ(run_clothsim(args).exit_code, 0);
}

TEST(CmdRun, StrictSucceedsWhenEveryStepConverged) {
  const CliResult r = run_clothsim({"run", shipped("stiff.yaml"), "--duration", "0.1", "--strict"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(" 0 steps not converged"), std::string::npos) << r.out;
}

TEST(CmdRun, ADivergedRunsLastPictureIsItsLastFiniteStateAtTheReportedTime) {
  const std::string dir = scratch_dir("run_diverged_frames");
  const CliResult r = run_clothsim({"run", shipped("stiff.yaml"), "--integrator", "explicit_euler", "--frames",
                                    dir, "--set", "render.width=160", "--set", "render.height=90"});
  ASSERT_EQ(r.exit_code, 3) << r.err;
  const auto [step, t] = reported_divergence(r.err);
  ASSERT_GT(step, 0) << r.err;
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  ASSERT_GE(names.size(), 2u);
  // Not the last output frame held: the state at the divergence's own time, which lies after
  // the previous frame's, shown as the clip's last picture.
  const double last_t = png_time(dir + "/" + names.back()), previous_t = png_time(dir + "/" + names[names.size() - 2]);
  EXPECT_NEAR(last_t, t, 1e-6 * std::max(1.0, t)) << "the picture's time is the one run reports";
  EXPECT_GT(last_t, previous_t);
  const Image last = read_png(dir + "/" + names.back());
  const Image previous = read_png(dir + "/" + names[names.size() - 2]);
  // The banner is there: red pixels in the middle band that the previous frame lacks.
  int red = 0;
  for (int y = last.height * 4 / 10; y < last.height * 6 / 10; ++y)
    for (int x = 0; x < last.width; ++x) {
      const std::uint8_t* p = last.pixel(x, y);
      red += p[0] > 180 && p[1] < 120 && p[2] < 120 && !(previous.pixel(x, y)[0] == p[0]);
    }
  EXPECT_GT(red, 10);
}

TEST(CmdRun, TheDivergenceStepIsTheSameWhateverIsWritten) {
  const std::string dir = scratch_dir("run_diverged_modes");
  const std::vector<std::string> base{"run", shipped("stiff.yaml"), "--integrator", "explicit_euler",
                                      "--set", "render.width=64", "--set", "render.height=64"};
  std::vector<std::pair<long, double>> seen;
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--state", dir + "/s.csv"}, {"--frames", dir + "/f"}, {"--video", dir + "/v.mp4"},
        {"--still", "1.5", "-o", dir + "/still.png"}, {"--metrics", dir + "/m.csv"}}) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    const CliResult r = run_clothsim(args);
    ASSERT_EQ(r.exit_code, 3) << r.err;
    seen.push_back(reported_divergence(r.err));
  }
  for (const auto& s : seen) {
    EXPECT_EQ(s.first, seen.front().first);
    EXPECT_EQ(s.second, seen.front().second);
  }
}

// Runs a bad command and checks: the exit code, one line on stderr containing `expected`,
// and nothing left in `dir` but the files that were there before.
void expect_rejected(const std::vector<std::string>& args, int code, const std::string& expected,
                     const std::string& dir, const std::vector<std::string>& files_before) {
  const CliResult r = run_clothsim(args);
  EXPECT_EQ(r.exit_code, code) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << "stderr: " << r.err;
  EXPECT_TRUE(only_files(dir, files_before)) << "something was left in " << dir;
}

TEST(CmdRun, AStillAloneRunsOnlyToItsTimeAndWritesOnePng) {
  const std::string dir = scratch_dir("run_still");
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--still", "0.25", "--out", dir + "/s.png",
                                    "--set", "render.width=320", "--set", "render.height=180"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2500 steps to t = 0.25 s"), std::string::npos) << r.out;
  EXPECT_TRUE(only_files(dir, {"s.png"}));
  const std::string png = slurp(dir + "/s.png");
  ASSERT_GT(png.size(), 24u);
  const auto be32 = [&](std::size_t at) {
    return (unsigned(static_cast<unsigned char>(png[at])) << 24) | (unsigned(static_cast<unsigned char>(png[at + 1])) << 16) |
           (unsigned(static_cast<unsigned char>(png[at + 2])) << 8) | unsigned(static_cast<unsigned char>(png[at + 3]));
  };
  EXPECT_EQ(be32(16), 320u);  // IHDR width and height
  EXPECT_EQ(be32(20), 180u);
  const std::string outside = scratch_dir("run_still_outside");
  expect_rejected({"run", shipped("drape.yaml"), "--still", "9", "--out", outside + "/s.png"}, 2,
                  "--still: time", outside, {});
  expect_rejected({"run", shipped("drape.yaml"), "--still", "1"}, 2, "--still needs -o/--output", outside, {});
}

TEST(CmdRun, BadScenesAreOneLineErrorsWithFileLineKeyAndExitTwo) {
  const std::string dir = scratch_dir("run_bad_scenes");
  struct Case { const char* name; std::string text; std::string expected; };
  const std::vector<Case> cases = {
      {"empty.yaml", "", "empty.yaml: empty scene file"},
      {"junk.yaml", std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10), "junk.yaml:1: not a text file"},
      {"tabs.yaml", "cloth:\n\tparticles: [3, 3]\n", "tabs.yaml:2: tab in indentation"},
      {"broken.yaml", "cloth: {particles: [3, 3]\n", "broken.yaml:1: invalid YAML"},  // where the { opens
      {"type.yaml", "cloth:\n  particles: [3, 3]\n  size: big\n", "type.yaml:3: cloth.size: expected"},
      {"unknown.yaml", "cloth: {particles: [3, 3]}\nwind: 3\n", "unknown.yaml:2: wind: unknown key"},
      {"mass.yaml", "cloth:\n  particles: [3, 3]\n  particle_mass: -2\n", "mass.yaml:3: cloth.particle_mass: value -2 out of range"},
      {"zero_mass.yaml", "cloth:\n  particles: [3, 3]\n  particle_mass: 0\n", "zero_mass.yaml:3: cloth.particle_mass"},
      {"res.yaml", "cloth:\n  particles: [0, 3]\n", "res.yaml:2: cloth.particles[0]: value 0 out of range"},
      {"dt.yaml", "dt: 0\ncloth: {particles: [3, 3]}\n", "dt.yaml:1: dt: value 0 out of range"},
      {"duration.yaml", "duration: -1\ncloth: {particles: [3, 3]}\n", "duration.yaml:1: duration"},
      {"pin.yaml", "cloth:\n  particles: [3, 3]\n  pinned: [[0, 0], [5, 1]]\n", "pin.yaml:3: cloth.pinned.1: particle [5, 1] is outside the 3 x 3 grid"},
      {"integ.yaml", "integrator: verlet\ncloth: {particles: [3, 3]}\n", "integ.yaml:1: integrator: unknown integrator 'verlet'"},
  };
  std::vector<std::string> files;
  for (const Case& c : cases) files.push_back(fs::path(write_file(dir, c.name, c.text)).filename());
  for (const Case& c : cases)
    expect_rejected({"run", dir + "/" + c.name, "--metrics", dir + "/m.csv", "--state", dir + "/s.csv"},
                    2, c.expected, dir, files);
  fs::create_directories(dir + "/subdir");
  files.push_back("subdir");
  expect_rejected({"run", dir + "/missing.yaml", "--state", dir + "/s.csv"}, 2, "missing.yaml: cannot open", dir, files);
  expect_rejected({"run", dir + "/subdir", "--state", dir + "/s.csv"}, 2, "is a directory", dir, files);
}

TEST(CmdRun, BadOptionsAreOneLineErrorsAndExitTwo) {
  const std::string dir = scratch_dir("run_bad_options");
  const std::string scene = shipped("spring.yaml");
  expect_rejected({"run", scene, "--integrator", "leapfrog", "--state", dir + "/s.csv"}, 2,
                  "--integrator: unknown integrator 'leapfrog'", dir, {});
  expect_rejected({"run", scene, "--dt", "0", "--state", dir + "/s.csv"}, 2, "--dt: must be", dir, {});
  expect_rejected({"run", scene, "--dt", "-1e-3", "--state", dir + "/s.csv"}, 2, "--dt: must be", dir, {});
  expect_rejected({"run", scene, "--dt", "1/0", "--state", dir + "/s.csv"}, 2, "--dt: '1/0' is not a number", dir, {});
  expect_rejected({"run", scene, "--duration", "-1", "--state", dir + "/s.csv"}, 2, "--duration: must be", dir, {});
  expect_rejected({"run", scene, "--set", "cloth.springs.structural.stiffnes=5", "--state", dir + "/s.csv"}, 2,
                  "--set cloth.springs.structural.stiffnes=5: unknown key", dir, {});
  expect_rejected({"run", scene, "--set", "dt", "--state", dir + "/s.csv"}, 2, "expected KEY=VALUE", dir, {});
  expect_rejected({"run", scene, "--set", "spheres.0.radius=0.8", "--state", dir + "/s.csv"}, 2,
                  "spring.yaml: --set spheres.0.radius=0.8: the scene has no spheres[0] (it has no spheres: give the "
                  "whole list, --set 'spheres=[...]')",
                  dir, {});
  expect_rejected({"run", scene, "--frobnicate"}, 2, "frobnicate", dir, {});
}

// Every output makes its missing folders, as --frames does (README's run --export out/drape.pc2).
TEST(CmdRun, EveryOutputMakesItsMissingFolders) {
  const std::string dir = scratch_dir("run_makes_folders");
  const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.1", "--metrics", dir + "/a/b/m.csv",
                                    "--state", dir + "/c/s.csv", "--export", dir + "/out/spring.pc2", "--quiet"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"/a/b/m.csv", "/c/s.csv", "/out/spring.pc2", "/out/spring.obj"})
    EXPECT_TRUE(fs::exists(dir + f)) << f;
}

// A 10-frame rerun over a 31-frame export left the 31 files (--frames removes its later PNGs).
TEST(CmdRun, AShorterExportRerunLeavesNoFrameOfTheLongerRun) {
  const std::string dir = scratch_dir("run_export_rerun");
  for (const std::string& path : {dir + "/obj/frame_%05d.obj", dir + "/ply/frame_%05d.ply", dir + "/v.pvd"}) {
    for (const char* duration : {"1", "0.3"}) {
      const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--duration", duration, "--export", path, "--quiet"});
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    const std::string folder = fs::path(path).extension() == ".pvd" ? dir + "/v" : fs::path(path).parent_path().string();
    const auto files = std::distance(fs::directory_iterator(folder), fs::directory_iterator{});
    EXPECT_EQ(files, 10) << path << ": frames 0 to 9 at 30 fps, none of the second second";
  }
  const std::string pvd = slurp(dir + "/v.pvd");
  EXPECT_EQ(std::count(pvd.begin(), pvd.end(), '\n'), 5 + 10) << "an index of the ten frames on disk";
}

// A signal mid-export said "nothing kept" without naming the PVD index or PC2 it never wrote.
TEST(CmdRun, ASignalMidExportNamesTheIndexOrCacheNotWritten) {
  for (const char* name : {"v.pvd", "c.pc2"}) {
    const std::string dir = scratch_dir(std::string("run_export_signal_") + name);
    const std::string path = dir + "/" + name;
    const bool pvd = fs::path(path).extension() == ".pvd";
    // The PVD's third frame on disk, or (PC2, whose frames stream into a nameless file) 2 s in.
    const StoppedResult r =
        pvd ? run_clothsim_interrupted_after_file({"run", shipped("drape.yaml"), "--duration", "60", "--export", path},
                                                  dir + "/v/cloth_00002.vtp", SIGTERM)
            : run_clothsim_interrupted({"run", shipped("drape.yaml"), "--duration", "60", "--export", path}, 2.0,
                                       SIGTERM);
    EXPECT_EQ(r.exit_code, 143) << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    const std::string not_written = pvd ? "not written: " + path
                                        : "not written: " + path + ", " + dir + "/c.obj, " + dir + "/c.sphere0.pc2, " +
                                              dir + "/c.sphere0.obj";
    EXPECT_NE(r.err.find(not_written), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path));
    if (pvd) EXPECT_NE(r.err.find(" VTP files in " + dir + "/v/"), std::string::npos) << r.err;
  }
}

// An output that is a FIFO nobody reads blocks its open until the signal: the stop is said
// as the signal's, not as "cannot write m.csv: Interrupted system call".
TEST(CmdRun, AFifoOutputUnderSigtermSaysStoppedBySigterm) {
  for (const char* option : {"--metrics", "--state", "--summary"}) {
    const std::string dir = scratch_dir(std::string("run_fifo_") + (option + 2));
    const std::string fifo = dir + "/out";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    const StoppedResult r =
        run_clothsim_interrupted({"run", shipped("spring.yaml"), "--duration", "0.2", option, fifo, "--quiet"}, 1.5,
                                 SIGTERM);
    EXPECT_EQ(r.exit_code, 143) << option << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("clothsim: stopped by SIGTERM", 0), 0u) << option << ": " << r.err;
  }
}

// --max-memory left the export's buffers out (1024² with --export: estimated 592 MB, peaks of
// 863-1072 MiB): a budget the run alone fits is refused with the export, naming it.
TEST(CmdRun, MaxMemoryCountsTheExport) {
  const std::string dir = scratch_dir("run_export_memory");
  const std::vector<std::string> run = {"run", shipped("drape.yaml"), "--set", "cloth.particles=[256,256]",
                                        "--duration", "0.001", "--max-memory", "125M", "--quiet"};
  EXPECT_EQ(run_clothsim(run).exit_code, 0) << "the run alone: an estimated 112 MB";
  std::vector<std::string> exported = run;
  exported.insert(exported.end(), {"--export", dir + "/x.pvd"});
  const CliResult r = run_clothsim(exported);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("needs an estimated 150 MB"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("export 37.5 MB"), std::string::npos) << r.err;
  EXPECT_TRUE(only_files(dir, {})) << "refused before any work";
}

TEST(CmdRun, UnwritableOutputsFailBeforeAnyWorkWithExitOne) {
  const std::string dir = scratch_dir("run_bad_outputs");
  const std::string scene = shipped("spring.yaml");
  const std::string file = write_file(dir, "plain", "x");
  expect_rejected({"run", scene, "--metrics", file + "/sub/m.csv"}, 1, "cannot make its folder", dir, {"plain"});
  expect_rejected({"run", scene, "--state", file + "/s.csv"}, 1, "cannot write --state", dir, {"plain"});
  expect_rejected({"run", scene, "--metrics", dir}, 1, "is a directory", dir, {"plain"});
}

TEST(CmdValidate, AcceptsEveryShippedSceneAndSaysWhatItModels) {
  for (const char* name : {"drape.yaml", "four_balls.yaml", "curtain.yaml", "spring.yaml", "chain.yaml", "stiff.yaml"}) {
    const CliResult r = run_clothsim({"validate", shipped(name)});
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_NE(r.out.find("valid scene"), std::string::npos) << r.out;
  }
  const CliResult drape = run_clothsim({"validate", shipped("drape.yaml")});
  EXPECT_NE(drape.out.find("25 x 25 particles (4 pinned), 3502 springs"), std::string::npos) << drape.out;
}

TEST(CmdValidate, PrintsTheStiffnessEstimateAndEachExplicitMethodsLimit) {
  const CliResult r = run_clothsim({"validate", shipped("drape.yaml")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // dt = 1e-4 s is inside the textbook methods' predicted limits, but above Verlet's: its
  // predicted velocity halves the damped limit (1 / c against symplectic Euler's 2 / c).
  EXPECT_NE(r.err.find("dt = 0.0001 s is above the predicted step limit of velocity_verlet (5.55e-05 s), "
                       "yoshida4 (5.07e-05 s)\n"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.out.find("stiffness estimate: w_max = 692.8 rad/s, 2/w_max = 0.00289 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("predicted step limits: explicit_euler 0.000111 s, symplectic_euler 0.000111 s, "
                       "midpoint 0.000111 s, rk4 0.000155 s, velocity_verlet 5.55e-05 s, yoshida4 5.07e-05 s, imex 0.00289 s; "
                       "implicit_euler: none"),
            std::string::npos)
      << r.out;
}

TEST(CmdValidate, WarnsWhenTheScenesDtIsAboveAPredictedLimit) {
  const CliResult r = run_clothsim({"validate", shipped("drape.yaml"), "--dt", "1e-3"});
  EXPECT_EQ(r.exit_code, 0) << "a warning, not an error";
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("warning: " + shipped("drape.yaml") + ": dt = 0.001 s is above the predicted step limit of "
                       "explicit_euler (0.000111 s), symplectic_euler (0.000111 s), midpoint (0.000111 s), rk4 (0.000155 s), "
                       "velocity_verlet (5.55e-05 s), yoshida4 (5.07e-05 s); "
                       "the scene's integrator symplectic_euler is likely to diverge"),
            std::string::npos)
      << r.err;
  // Undamped, explicit Euler and midpoint are unstable at every step: always above.
  const CliResult spring = run_clothsim({"validate", shipped("spring.yaml"), "--set", "cloth.springs.structural.damping=0"});
  EXPECT_NE(spring.err.find("explicit_euler (unstable at every step), midpoint (unstable at every step)"),
            std::string::npos)
      << spring.err;
}

TEST(CmdValidate, RejectsABadSceneWithItsLine) {
  const std::string dir = scratch_dir("validate_bad");
  write_file(dir, "bad.yaml", "cloth:\n  particles: [3, 3]\n  plane: yz\n");
  const CliResult r = run_clothsim({"validate", dir + "/bad.yaml"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml:3: cloth.plane: unknown plane 'yz'"), std::string::npos) << r.err;
}

// A value is escaped once, where the message echoes it (docs/scenes.md: a newline shows as
// 'a\nb'), and main's last guard does not escape it again, whichever way the value came in.
TEST(Cli, AnEchoedValueIsEscapedOnceOnItsOneLine) {
  const std::string dir = scratch_dir("validate_escaped_once");
  const std::string scene = write_file(dir, "nl.yaml", "cloth: {particles: [3, 3]}\nintegrator: \"a\\nb\"\n");
  const auto expect_one_line = [&](const std::vector<std::string>& args, const std::string& expected) {
    const CliResult r = run_clothsim(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("'a\\\\nb'"), std::string::npos) << "the value escaped twice: " << r.err;
    EXPECT_TRUE(only_files(dir, {"nl.yaml"}));
  };
  // The YAML string "a\nb" holds a newline: shown as 'a\nb'.
  expect_one_line({"validate", scene}, "nl.yaml:2: integrator: unknown integrator 'a\\nb' (expected one of:");
  // The same from --set, whose text as typed holds a backslash: shown escaped once, as \\.
  expect_one_line({"validate", shipped("spring.yaml"), "--set", "integrator=\"a\\nb\""},
                  "spring.yaml: --set integrator=\"a\\\\nb\": unknown integrator 'a\\nb' (expected one of:");
  // An option's value holding a newline, echoed by clothsim's message and by a CLI11 validator's.
  expect_one_line({"validate", shipped("spring.yaml"), "--integrator", "a\nb"}, "--integrator: unknown integrator 'a\\nb'");
  expect_one_line({"validate", shipped("spring.yaml"), "--max-memory", "a\nb"}, "--max-memory: 'a\\nb' is not a size");
}

TEST(Cli, HelpExplainsEverySubcommand) {
  const CliResult top = run_clothsim({"--help"});
  EXPECT_EQ(top.exit_code, 0);
  for (const char* sub : {"run", "compare", "bench", "stability", "validate", "encode", "imgdiff"}) {
    EXPECT_NE(top.out.find(sub), std::string::npos) << sub;
    const CliResult help = run_clothsim({sub, "--help"});
    EXPECT_EQ(help.exit_code, 0) << sub;
    EXPECT_GT(help.out.size(), 100u) << sub;
  }
  EXPECT_EQ(run_clothsim({}).exit_code, 2);
}

TEST(Cli, AMisspeltCommandIsPointedAtTheCommandItMeant) {
  const CliResult r = run_clothsim({"comapre", shipped("drape.yaml")});  // it said "A subcommand is required"
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("clothsim: unknown command 'comapre' (did you mean compare? the commands: run, compare, "),
            std::string::npos)
      << r.err;
}

TEST(CmdRun, AStillNamedForAnotherFormatIsRefused) {
  const std::string dir = scratch_dir("run_still_names");
  for (const char* name : {"/x.jpg", "/y.gif"}) {  // PNG bytes were written under these names
    const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--still", "0.1", "-o", dir + name});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("-o/--output: '" + dir + name + "' names a "), std::string::npos) << r.err;
  }
  EXPECT_EQ(run_clothsim({"run", shipped("spring.yaml"), "--still", "0.1", "-o", dir + "/z.PNG", "--quiet"}).exit_code, 0);
  EXPECT_TRUE(only_files(dir, {"z.PNG"}));
}

TEST(Cli, HelpListsEveryExitCodeOfTheContract) {
  const CliResult help = run_clothsim({"run", "--help"});
  for (const char* code : {"0 success", "1 runtime failure", "2 bad usage", "3 the simulation diverged",
                           "4 a step did not converge", "5 the run reads WRONG", "130 / 143 stopped by SIGINT"})
    EXPECT_NE(help.out.find(code), std::string::npos) << code << "\n" << help.out;
}

TEST(CmdRun, StoppedBySigtermExits143AndLeavesNoFile) {
  // A minute of the drape takes far longer than the 2 s before SIGTERM arrives. --foreground:
  // without it timeout signals the child and then its whole process group, a second SIGTERM
  // that (by design) kills at once when it lands after the first was handled.
  const std::string dir = scratch_dir("run_sigterm");
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--duration", "60", "--metrics", dir + "/m.csv"},
                                   "timeout --foreground --preserve-status -s TERM 2");
  EXPECT_EQ(r.exit_code, 143) << "128 + SIGTERM\n" << r.err;
  EXPECT_NE(r.err.find("stopped by SIGTERM"), std::string::npos) << r.err;
  EXPECT_TRUE(only_files(dir, {})) << "no metrics and no temporary";
}

// At a step of 1 ns the first frame is 33 million steps away: only a check inside the stepping
// loop answers. The bound is generous (a shared machine), far below stepping to that frame.
TEST(CmdRun, StopsWithinTheBoundAtATinyStepOnEitherSignalLeavingNothing) {
  for (const int signal : {SIGINT, SIGTERM}) {
    const std::string dir = scratch_dir("run_tiny_dt_" + std::to_string(signal));
    const StoppedResult r = run_clothsim_interrupted(
        {"run", shipped("drape.yaml"), "--set", "dt=1e-9", "--duration", "1", "--state", dir + "/s.csv",
         "--metrics", dir + "/m.csv", "--video", dir + "/v.mp4", "--set", "render.width=64",
         "--set", "render.height=64"},
        1.0, signal);
    EXPECT_EQ(r.exit_code, 128 + signal) << r.err;
    EXPECT_LT(r.seconds_to_exit, 2.0) << "the issue's bound is 0.5 s on an idle machine";
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(std::string("stopped by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") + " at t = "),
              std::string::npos) << r.err;
    EXPECT_NE(r.err.find("nothing kept; not written: " + dir + "/m.csv, " + dir + "/v.mp4, " + dir + "/s.csv"),
              std::string::npos) << r.err;
    EXPECT_TRUE(only_files(dir, {})) << "no state, metrics or video, and no temporary";
  }
}

// A second signal of either kind ends the process at once, whatever the first is doing: both
// arrive together (the process stopped, signalled twice, continued), the first is handled,
// the second kills before a word is written. Nothing is left: outputs have no name yet.
TEST(CmdRun, ASecondSignalOfEitherKindKillsAtOnceLeavingNothing) {
  const std::string dir = scratch_dir("run_second_signal");
  const StoppedResult r = run_clothsim_signalled(
      {"run", shipped("drape.yaml"), "--set", "dt=1e-9", "--duration", "1", "--state", dir + "/s.csv", "--video",
       dir + "/v.mp4", "--set", "render.width=64", "--set", "render.height=64"},
      1.0, {SIGSTOP, SIGTERM, SIGINT, SIGCONT});
  EXPECT_TRUE(r.exit_code == 128 + SIGINT || r.exit_code == 128 + SIGTERM) << r.exit_code << "\n" << r.err;
  EXPECT_EQ(r.err.find("stopped by"), std::string::npos) << "killed by the second, not stopped cleanly\n" << r.err;
  EXPECT_LT(r.seconds_to_exit, 2.0);
  EXPECT_TRUE(only_files(dir, {}));
}

// A file-size limit (ulimit -f 16: 8 kB in dash's 512-byte blocks) makes every output's
// write fail with EFBIG, as a full disk fails with ENOSPC: exit 1, one line with the system's
// reason, and nothing under the requested name (nor a temporary beside it).
TEST(CmdRun, AWriteFailureOnAnyOutputIsOneLineExit1AndLeavesNothing) {
  const std::vector<std::pair<std::string, std::string>> outputs = {
      {"--state", "s.csv"}, {"--metrics", "m.csv"}, {"--video", "v.mp4"}, {"--frames", "f"}};
  for (const auto& [option, name] : outputs) {
    const std::string dir = scratch_dir("run_fsize_" + name);
    const CliResult r = run_clothsim(
        {"run", shipped("drape.yaml"), "--duration", "2", option, dir + "/" + name}, "ulimit -f 16;");
    EXPECT_EQ(r.exit_code, 1) << option << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1) << option << "\n" << r.err;
    EXPECT_NE(r.err.find("cannot write " + dir + "/" + name), std::string::npos) << option << "\n" << r.err;
    EXPECT_NE(r.err.find("File too large"), std::string::npos) << option << "\n" << r.err;
    // Nothing under the name, no temporary; for --frames no PNG, whole or partial, and not
    // the directory it made either.
    EXPECT_TRUE(only_files(dir, {})) << option;
  }
}

// SIGKILL cannot be caught: outputs are created without a name (O_TMPFILE) and named only
// when complete, so a killed run leaves nothing at all, not even a hidden temporary.
TEST(CmdRun, AWriteFailureSaysWhatItKeptAndDropsTheRest) {
  // The PNGs written before the failure are whole and stay, as after a signal; the outputs
  // not finished are dropped, and the line says so.
  const std::string dir = scratch_dir("run_fsize_several");
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--duration", "2", "--set", "render.width=320",
                                    "--set", "render.height=180", "--frames", dir + "/f", "--video", dir + "/v.mp4",
                                    "--state", dir + "/s.csv"},
                                   "ulimit -f 60;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("File too large; kept "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" PNGs in " + dir + "/f"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not written: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(dir + "/s.csv"), std::string::npos) << "the state, written after the run\n" << r.err;
  EXPECT_FALSE(fs::exists(dir + "/v.mp4"));
  EXPECT_FALSE(fs::exists(dir + "/s.csv"));
}

TEST(CmdRun, SigkillLeavesNoFileAndNoTemporary) {
  const std::string dir = scratch_dir("run_sigkill");
  const StoppedResult r = run_clothsim_interrupted(
      {"run", shipped("drape.yaml"), "--set", "dt=1e-9", "--duration", "1", "--state", dir + "/s.csv", "--metrics",
       dir + "/m.csv", "--video", dir + "/v.mp4", "--set", "render.width=64", "--set", "render.height=64"},
      1.0, SIGKILL);
  EXPECT_EQ(r.exit_code, 128 + SIGKILL);
  EXPECT_TRUE(only_files(dir, {}));
}

TEST(CmdRun, AnInterruptedFramesRunSaysItKeptThePngsItWrote) {
  const std::string dir = scratch_dir("run_interrupt_frames");
  const StoppedResult r = run_clothsim_interrupted_after_file(
      {"run", shipped("drape.yaml"), "--set", "dt=1e-9", "--duration", "1", "--frames", dir + "/f", "--set", "render.width=64",
       "--set", "render.height=64"},
      dir + "/f/frame_00000.png", SIGINT);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_NE(r.err.find("kept 1 PNG in " + dir + "/f"), std::string::npos) << "frame 0 needs no step\n" << r.err;
  EXPECT_TRUE(only_files(dir + "/f", {"frame_00000.png"}));
}

}  // namespace
}  // namespace clothsim::testing

namespace clothsim::testing {
namespace {

TEST(CmdRun, NoOverwriteRefusesAnExistingOutputBeforeAnyWorkAndLeavesItUntouched) {
  const std::string dir = scratch_dir("run_no_overwrite");
  const std::string metrics = write_file(dir, "m.csv", "mine\n");
  const auto before = fs::last_write_time(metrics);
  for (const char* flag : {"-n", "--no-overwrite"}) {
    const CliResult r = run_clothsim({"run", shipped("spring.yaml"), flag, "--metrics", metrics, "--state", dir + "/s.csv"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--metrics: " + metrics + " exists, and -n/--no-overwrite keeps it"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");  // no run: nothing to summarise
  }
  EXPECT_EQ(slurp(metrics), "mine\n");
  EXPECT_EQ(fs::last_write_time(metrics), before);
  EXPECT_TRUE(only_files(dir, {"m.csv"}));  // nor was the state written
  // Without -n the file is replaced, as before.
  ASSERT_EQ(run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.1", "--metrics", metrics}).exit_code, 0);
  EXPECT_NE(slurp(metrics), "mine\n");
}

TEST(CmdRun, NoOverwriteRefusesAFramesDirectoryHoldingFrames) {
  const std::string dir = scratch_dir("run_no_overwrite_frames");
  write_file(dir, "frame_00000.png", "not mine to lose");
  const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.1", "-n", "--frames", dir});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("already holds frames"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir + "/frame_00000.png"), "not mine to lose");
}

TEST(CmdRun, StillTakesDashOAndWidthHeightAsCompareDoes) {
  const std::string dir = scratch_dir("run_output_size");
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--still", "0.05", "-o", dir + "/a.png", "--width",
                                    "200", "--height", "120"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image a = read_png(dir + "/a.png");
  EXPECT_EQ(a.width, 200);
  EXPECT_EQ(a.height, 120);
  // --out stays as the old spelling of the same option.
  ASSERT_EQ(run_clothsim({"run", shipped("drape.yaml"), "--still", "0.05", "--out", dir + "/b.png", "--width", "200",
                          "--height", "120"}).exit_code, 0);
  EXPECT_EQ(read_png(dir + "/b.png").rgba, a.rgba);
  const CliResult bad = run_clothsim({"run", shipped("drape.yaml"), "--still", "0", "-o", dir + "/c.png", "--width", "8"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--width: must be from 16 to 8192 pixels"), std::string::npos) << bad.err;
}

TEST(CmdRun, FpsSetsHowManyFramesTheMetricsAndFramesHave) {
  const std::string dir = scratch_dir("run_fps");
  ASSERT_EQ(run_clothsim({"run", shipped("spring.yaml"), "--duration", "1", "--fps", "10", "--metrics", dir + "/m.csv"})
                .exit_code, 0);
  EXPECT_EQ(rows(dir + "/m.csv"), 1 + 11);  // header + frames at 0, 0.1, ..., 1 s
}

TEST(CmdRun, MetricsRowsSayTheSceneIntegratorAndStep) {
  const std::string dir = scratch_dir("run_metrics_columns");
  ASSERT_EQ(run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.1", "--integrator", "rk4", "--dt", "1/200",
                          "--metrics", dir + "/m.csv"}).exit_code, 0);
  std::ifstream in(dir + "/m.csv");
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_NE(header.find(",scene,integrator,dt,step_size,rejected_steps"), std::string::npos) << header;
  EXPECT_NE(first.find(",spring,rk4,0.005,0.005,0"), std::string::npos) << first;
}

TEST(CmdRun, PlotEnergyLabelsEachLineByItsMetricsColumns) {
  const std::string dir = scratch_dir("run_metrics_labels");
  for (const char* i : {"rk4", "midpoint"})
    ASSERT_EQ(run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.1", "--integrator", i, "--dt", "0.005",
                            "--metrics", dir + "/" + i + ".csv"}).exit_code, 0);
  ASSERT_EQ(run_clothsim({"run", shipped("chain.yaml"), "--duration", "0.01", "--metrics", dir + "/chain.csv"})
                .exit_code, 0);
  // tools/plot_energy.py's run_labels(), as the script calls it on these files (with the system
  // python, which has the matplotlib plot_common.py imports, as --plot prefers it).
  const std::string out = dir + "/labels.txt";
  const auto labels = [&](const std::string& files) {
    const std::string cmd = "cd " + shell_quote(dir) + " && /usr/bin/python3 -c \"import sys; sys.path.insert(0, '" +
                            std::string(CLOTHSIM_SCENES_DIR) + "/../tools'); import plot_energy as p, plot_common as c; "
                            "f = sys.argv[1:]; print(p.run_labels(f, [c.read_rows(x) for x in f]))\" " + files +
                            " >" + shell_quote(out) + " 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(out);
    return slurp(out);
  };
  EXPECT_EQ(labels("rk4.csv midpoint.csv"), "['rk4, dt = 0.005 s', 'midpoint, dt = 0.005 s']\n");
  EXPECT_EQ(labels("rk4.csv chain.csv"), "['spring: rk4, dt = 0.005 s', 'chain: symplectic_euler, dt = 0.0001 s']\n");
}

TEST(CmdRun, TheFixedPointRunsByItsNameAndItsMetricsSaySo) {
  // `run --integrator implicit_euler_fixed_point` exited 2, and --set implicit.solver=fixed_point
  // wrote rows labelled implicit_euler: two different methods' lines could not be told apart.
  const std::string dir = scratch_dir("run_fixed_point_name");
  const CliResult named = run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.05", "--integrator",
                                        "implicit_euler_fixed_point", "--metrics", dir + "/named.csv"});
  ASSERT_EQ(named.exit_code, 0) << named.err;
  EXPECT_NE(named.out.find("spring: implicit_euler_fixed_point, dt = "), std::string::npos) << named.out;
  EXPECT_EQ(named.out.find("Newton"), std::string::npos) << "the fixed point has no Newton solve to report";
  const CliResult set = run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.05", "--integrator",
                                      "implicit_euler", "--set", "implicit.solver=fixed_point", "--metrics",
                                      dir + "/set.csv"});
  ASSERT_EQ(set.exit_code, 0) << set.err;
  const std::string a = slurp(dir + "/named.csv"), b = slurp(dir + "/set.csv");
  EXPECT_EQ(a, b) << "the name and the scene key are one method";
  EXPECT_NE(a.find(",spring,implicit_euler_fixed_point,0.001,"), std::string::npos) << a;
  const CliResult newton = run_clothsim({"run", shipped("spring.yaml"), "--duration", "0.05", "--integrator",
                                         "implicit_euler", "--metrics", dir + "/newton.csv"});
  ASSERT_EQ(newton.exit_code, 0) << newton.err;
  EXPECT_NE(slurp(dir + "/newton.csv").find(",spring,implicit_euler,0.001,"), std::string::npos);
  EXPECT_NE(slurp(dir + "/newton.csv"), a) << "and a different method from backward Euler";
}

// NaN compares false with every bound: it is refused like a time outside the run.
TEST(CmdRun, AStillAtNanIsRefused) {
  const std::string dir = scratch_dir("run_still_nan");
  const CliResult r = run_clothsim({"run", shipped("spring.yaml"), "--still", "nan", "-o", dir + "/x.png"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--still: time nan s is outside the run"), std::string::npos) << r.err;
  EXPECT_TRUE(only_files(dir, {}));
}

TEST(CmdRun, ARerunsFramesHoldNoFrameOfALongerEarlierRun) {
  const std::string dir = scratch_dir("run_frames_rerun");
  const std::vector<std::string> base{"run", shipped("spring.yaml"), "--width", "64", "--height", "48", "--frames",
                                      dir + "/fr"};
  std::vector<std::string> longer = base, shorter = base;
  longer.insert(longer.end(), {"--duration", "0.5"});    // frames 0..15 at 30 fps
  shorter.insert(shorter.end(), {"--duration", "0.2"});  // frames 0..6
  ASSERT_EQ(run_clothsim(longer).exit_code, 0);
  ASSERT_EQ(run_clothsim(shorter).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir + "/fr/frame_00006.png"));
  EXPECT_FALSE(fs::exists(dir + "/fr/frame_00007.png")) << "a frame of the earlier, longer run";
  EXPECT_EQ(std::distance(fs::directory_iterator(dir + "/fr"), fs::directory_iterator()), 7);
}

TEST(CmdRun, ASceneFromAStreamIsBoundedByMaxMemory) {
  const CliResult r = run_clothsim({"validate", "/dev/zero", "--max-memory", "100M"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("/dev/zero: more than 25 MB read from this stream"), std::string::npos) << r.err;
}

TEST(CmdRun, ARunPastTheAddressSpaceLimitIsRefusedOnOneLineBeforeAllocating) {
  const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--set", "cloth.particles=[1024,1024]", "--duration",
                                    "2e-4", "--metrics", "/dev/null"},
                                   "ulimit -v 800000;");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("more than the address-space limit (ulimit -v 781 MB"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace clothsim::testing
