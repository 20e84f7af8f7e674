// `clothsim golden check|update MANIFEST.yaml` as users call it, and the project's own golden
// images (tests/golden/manifest.yaml) checked through it with each GL backend.
// CLOTHSIM_UPDATE_GOLDEN=1 makes the project's test rewrite them instead (after an intended
// change to the picture; commit the new images).
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {
namespace fs = std::filesystem;

bool updating_goldens() {
  const char* v = std::getenv("CLOTHSIM_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

void project_goldens_through(const std::string& backend) {
  const std::string manifest = std::string(CLOTHSIM_GOLDEN_DIR) + "/manifest.yaml";
  const std::string failures = scratch_dir("golden_" + backend);
  const CliResult r = updating_goldens()
                          ? run_clothsim({"golden", "update", manifest, "--gl", backend})
                          : run_clothsim({"golden", "check", manifest, "--gl", backend, "--failures", failures});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err
                            << "(if the change is intended: CLOTHSIM_UPDATE_GOLDEN=1 ctest -R ProjectGoldens)";
  EXPECT_NE(r.out.find(updating_goldens() ? "3 of 3 images written" : "3 of 3 images match"), std::string::npos) << r.out;
}

TEST(ProjectGoldens, MatchThroughEgl) { project_goldens_through("egl"); }
TEST(ProjectGoldens, MatchThroughOsmesa) { project_goldens_through("osmesa"); }

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// A user's directory: their own scene (the drape, copied) and a manifest beside it.
struct UserProject {
  std::string dir, scene, manifest, golden;
  explicit UserProject(const std::string& name) : dir(scratch_dir(name)) {
    scene = dir + "/my_drape.yaml";
    fs::copy_file(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", scene);
    manifest = dir + "/goldens.yaml";
    write(manifest, "size: [160, 90]\ngoldens:\n  - scene: my_drape.yaml\n    times: [0.05, 0.2]\n");
    golden = dir + "/my_drape_t200ms.png";
  }
  void change_scene() {  // a bigger ball: the cloth drapes differently
    std::string text = slurp(scene);
    text.replace(text.find("radius: 1.0"), 11, "radius: 1.4");
    write(scene, text);
  }
};

TEST(CmdGolden, UpdateWritesTheImagesAndCheckThenPasses) {
  UserProject p("golden_user_pass");
  const CliResult update = run_clothsim({"golden", "update", p.manifest});
  ASSERT_EQ(update.exit_code, 0) << update.err;
  EXPECT_TRUE(fs::exists(p.dir + "/my_drape_t50ms.png"));
  EXPECT_TRUE(fs::exists(p.golden));
  const CliResult check = run_clothsim({"golden", "check", p.manifest});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(check.out.find("golden: 2 of 2 images match"), std::string::npos) << check.out;
  EXPECT_TRUE(only_files(p.dir, {"my_drape.yaml", "goldens.yaml", "my_drape_t50ms.png", "my_drape_t200ms.png"}));
}

// A golden that is a FIFO with no reader blocks update's open until a signal breaks it off:
// that said "cannot write ...: Interrupted system call"; it is the signal's stop.
TEST(CmdGolden, AFifoGoldenUnderSigtermSaysStoppedBySigterm) {
  UserProject p("golden_fifo_sigterm");
  ASSERT_EQ(::mkfifo(p.golden.c_str(), 0644), 0);
  const StoppedResult r = run_clothsim_interrupted({"golden", "update", p.manifest}, 3.0, SIGTERM);
  EXPECT_EQ(r.exit_code, 143) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("clothsim: stopped by SIGTERM", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find("Interrupted system call"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p.dir + "/my_drape_t50ms.png")) << "update writes all or none";
}

TEST(CmdGolden, AChangedSceneFailsWithTheActualAndDiffImagesBesideAndUpdateRewrites) {
  UserProject p("golden_user_fail");
  ASSERT_EQ(run_clothsim({"golden", "update", p.manifest}).exit_code, 0);
  const std::string before = slurp(p.golden);
  p.change_scene();
  const CliResult check = run_clothsim({"golden", "check", p.manifest});
  EXPECT_EQ(check.exit_code, 1) << check.out << check.err;
  EXPECT_NE(check.out.find("FAIL  my_drape_t200ms.png"), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("golden: 0 of 2 images match"), std::string::npos) << check.out;
  const std::string actual = p.dir + "/my_drape_t200ms.actual.png", diff = p.dir + "/my_drape_t200ms.diff.png";
  EXPECT_TRUE(fs::exists(actual));
  EXPECT_TRUE(fs::exists(diff));
  EXPECT_NE(check.out.find(diff), std::string::npos) << check.out;

  const CliResult update = run_clothsim({"golden", "update", p.manifest});
  ASSERT_EQ(update.exit_code, 0) << update.err;
  EXPECT_NE(slurp(p.golden), before);
  const CliResult again = run_clothsim({"golden", "check", p.manifest});
  EXPECT_EQ(again.exit_code, 0) << again.out;
  EXPECT_FALSE(fs::exists(actual));  // the evidence of the old failure is gone
  EXPECT_FALSE(fs::exists(diff));
}

// --junit as a CI reads it: a real JUnit consumer (Debian's python3-junitparser) finds one
// test case per entry, the changed entry failed with its images' differences and its diff
// images as attachments, the unchanged one passed.
TEST(CmdGolden, JunitHasATestCasePerEntryThatAJunitReaderReads) {
  UserProject p("golden_user_junit");
  fs::copy_file(p.scene, p.dir + "/other.yaml");
  write(p.manifest, "size: [160, 90]\ngoldens:\n  - scene: my_drape.yaml\n    times: [0.05, 0.2]\n"
                    "  - scene: other.yaml\n    times: [1/20]\n");
  ASSERT_EQ(run_clothsim({"golden", "update", p.manifest}).exit_code, 0);
  p.change_scene();
  const std::string xml = p.dir + "/golden.xml";
  const CliResult check = run_clothsim({"golden", "check", p.manifest, "--junit", xml});
  EXPECT_EQ(check.exit_code, 1) << check.out << check.err;
  ASSERT_TRUE(fs::exists(xml)) << check.err;
  const std::string reader = p.dir + "/read.py";
  write(reader,
        "import sys\n"
        "try:\n"
        "    from junitparser import JUnitXml, Failure\n"
        "except ImportError:\n"
        "    sys.exit(77)\n"
        "suites = list(JUnitXml.fromfile(sys.argv[1]))\n"
        "cases = [c for s in suites for c in s]\n"
        "print(len(suites), len(cases))\n"
        "for c in cases:\n"
        "    failed = [r for r in c.result if isinstance(r, Failure)]\n"
        "    props = [q.get('value') for q in c._elem.iter('property')]  # junitparser 2 has no TestCase.properties\n"
        "    print(c.name, 'FAIL' if failed else 'ok', len(props), props[0] if props else '-')\n"
        "    if failed: print('TEXT', failed[0].text.count('FAIL  '))\n");
  const CliResult read = run_process({"/usr/bin/python3", reader, xml});
  if (read.exit_code == 77) GTEST_SKIP() << "python3-junitparser not installed (tools/install-deps.sh test installs it)";
  ASSERT_EQ(read.exit_code, 0) << read.err;
  EXPECT_NE(read.out.find("1 2\n"), std::string::npos) << read.out;
  const std::string diff200 = p.dir + "/my_drape_t200ms.diff.png";
  EXPECT_NE(read.out.find("my_drape FAIL 2 " + p.dir + "/my_drape_t50ms.diff.png"), std::string::npos) << read.out;
  EXPECT_NE(read.out.find("TEXT 2"), std::string::npos) << read.out;  // both images' lines
  EXPECT_NE(read.out.find("other ok 0 -"), std::string::npos) << read.out;
  EXPECT_TRUE(fs::exists(diff200));
}

// A corrupt golden is its own FAIL row (the common CI case: a Git LFS pointer), and every
// other golden is still checked and listed in --csv.
TEST(CmdGolden, ACorruptGoldenFailsItsOwnRowAndTheOthersAreStillChecked) {
  struct Case {
    const char* what;
    std::function<void(const std::string&)> spoil;
    const char* says;
  };
  const std::vector<Case> cases = {
      {"lfs", [](const std::string& g) { write(g, "version https://git-lfs.github.com/spec/v1\noid sha256:ab\nsize 9\n"); },
       "a Git LFS pointer"},
      {"text", [](const std::string& g) { write(g, "not a png"); }, "unreadable golden"},
      {"empty", [](const std::string& g) { write(g, ""); }, "unreadable golden"},
      {"truncated", [](const std::string& g) { const std::string b = slurp(g); write(g, b.substr(0, b.size() / 2)); },
       "unreadable golden"},
      {"directory", [](const std::string& g) { fs::remove(g); fs::create_directory(g); }, "not a regular file"},
  };
  for (const Case& c : cases) {
    UserProject p(std::string("golden_user_corrupt_") + c.what);
    ASSERT_EQ(run_clothsim({"golden", "update", p.manifest}).exit_code, 0);
    c.spoil(p.dir + "/my_drape_t50ms.png");
    const std::string csv = p.dir + "/c.csv";
    const CliResult check = run_clothsim({"golden", "check", p.manifest, "--csv", csv});
    EXPECT_EQ(check.exit_code, 1) << c.what << ": " << check.out << check.err;
    EXPECT_NE(check.out.find("FAIL  my_drape_t50ms.png"), std::string::npos) << c.what << ": " << check.out;
    EXPECT_NE(check.out.find(c.says), std::string::npos) << c.what << ": " << check.out;
    EXPECT_NE(check.out.find("golden: 1 of 2 images match"), std::string::npos) << c.what << ": " << check.out;
    const std::string rows = slurp(csv);
    EXPECT_NE(rows.find("my_drape_t50ms.png"), std::string::npos) << rows;
    EXPECT_NE(rows.find("my_drape_t200ms.png"), std::string::npos) << rows;
  }
}

TEST(CmdGolden, AManifestsSecondDocumentIsRefusedEvenBroken) {
  UserProject p("golden_user_two_docs");
  for (const char* second : {"---\ngoldens: []\n", "---\ngoldens: [\n"}) {
    write(p.manifest, "size: [160, 90]\ngoldens:\n  - scene: my_drape.yaml\n    times: [0.05]\n" + std::string(second));
    const CliResult r = run_clothsim({"golden", "check", p.manifest});
    EXPECT_EQ(r.exit_code, 2) << second << r.out << r.err;
    EXPECT_NE(r.err.find(p.manifest + ":"), std::string::npos) << r.err;  // its file and line
    EXPECT_TRUE(r.err.find("second YAML document") != std::string::npos || r.err.find("invalid YAML") != std::string::npos)
        << r.err;
  }
}

// kind: compare goldens the grid compare draws: its lanes side by side at the entry's size.
TEST(CmdGolden, ACompareEntryGoldensTheGridCompareDraws) {
  UserProject p("golden_user_compare");
  write(p.manifest, "size: [320, 180]\ngoldens:\n  - scene: my_drape.yaml\n    kind: compare\n"
                    "    integrators: [rk4@4e-4, midpoint]\n    times: [0.1]\n");
  const CliResult update = run_clothsim({"golden", "update", p.manifest});
  ASSERT_EQ(update.exit_code, 0) << update.out << update.err;
  const std::string golden = p.dir + "/my_drape_t100ms.png";
  ASSERT_TRUE(fs::exists(golden));
  // The grid compare writes for the same lanes and time, to the pixel.
  const CliResult grid = run_clothsim({"compare", p.scene, "--integrators", "rk4@4e-4,midpoint", "--width", "320",
                                       "--height", "180", "--still", "0.1", "-o", p.dir + "/grid.png", "--quiet"});
  ASSERT_EQ(grid.exit_code, 0) << grid.err;
  const CliResult same = run_clothsim({"imgdiff", golden, p.dir + "/grid.png", "--threshold", "0", "--max-rms", "0"});
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  fs::remove(p.dir + "/grid.png");
  const CliResult check = run_clothsim({"golden", "check", p.manifest});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(check.out.find("golden: 1 of 1 images match"), std::string::npos) << check.out;
  p.change_scene();
  const CliResult changed = run_clothsim({"golden", "check", p.manifest});
  EXPECT_EQ(changed.exit_code, 1) << changed.out << changed.err;
  EXPECT_TRUE(fs::exists(p.dir + "/my_drape_t100ms.diff.png"));
  // A bad lane is the manifest's line and key, before anything runs.
  write(p.manifest, "goldens:\n  - scene: my_drape.yaml\n    kind: compare\n    integrators: [rk5]\n    times: [0.1]\n");
  const CliResult bad = run_clothsim({"golden", "check", p.manifest});
  EXPECT_EQ(bad.exit_code, 2) << bad.out << bad.err;
  EXPECT_NE(bad.err.find("goldens[0].integrators"), std::string::npos) << bad.err;
}

TEST(CmdGolden, AMissingGoldenFailsAndSaysHowToMakeIt) {
  UserProject p("golden_user_missing");
  const CliResult check = run_clothsim({"golden", "check", p.manifest});
  EXPECT_EQ(check.exit_code, 1);
  EXPECT_NE(check.out.find("missing (`clothsim golden update` writes it)"), std::string::npos) << check.out;
}

TEST(CmdGolden, ABadManifestExitsTwoWithFileLineAndKey) {
  const std::string dir = scratch_dir("golden_bad_manifest");
  const struct {
    std::string text, message;
  } cases[] = {
      {"goldens:\n  - scene: a.yaml\n    tims: [1]\n", "m.yaml:3: goldens[0].tims: unknown key"},
      {"goldens:\n  - scene: a.yaml\n", "m.yaml:2: goldens[0].times: missing"},
      {"goldens:\n  - scene: a.yaml\n    times: [1, 0.5]\n", "m.yaml:3: goldens[0].times: expected increasing times"},
      {"size: [320, -1]\ngoldens:\n  - scene: a.yaml\n    times: [1]\n", "m.yaml:1: size[1]: value -1 out of range"},
      {"goldens:\n  - scene: a.yaml\n    times: [1]\n    integrator: rk5\n", "m.yaml:4: goldens[0].integrator: unknown integrator 'rk5'"},
      {"goldens:\n  - {scene: a.yaml, times: [1]}\n  - {scene: b/a.yaml, times: [1]}\n",
       "m.yaml:3: goldens[1].name: writes a_t1000ms.png as goldens[0] does"},
      {"tolerance: {max_rms: x}\ngoldens: []\n", "m.yaml:1: tolerance.max_rms: expected a number"},
  };
  for (const auto& c : cases) {
    write(dir + "/m.yaml", c.text);
    const CliResult r = run_clothsim({"golden", "check", dir + "/m.yaml"});
    EXPECT_EQ(r.exit_code, 2) << c.text;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  }
  // Named against the manifest too: a scene that is not there, a time past the scene's end.
  write(dir + "/m.yaml", "goldens:\n  - {scene: nowhere.yaml, times: [1]}\n");
  const CliResult r = run_clothsim({"golden", "check", dir + "/m.yaml"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("m.yaml:2: goldens[0].scene: not a scene file (missing, or a directory): "), std::string::npos) << r.err;
  fs::copy_file(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", dir + "/d.yaml");  // 5 s
  write(dir + "/m.yaml", "goldens:\n  - scene: d.yaml\n    times: [1, 9]\n");
  const CliResult late = run_clothsim({"golden", "update", dir + "/m.yaml"});
  EXPECT_EQ(late.exit_code, 2);
  EXPECT_EQ(line_count(late.err), 1) << late.err;
  // At the times key's line, not the entry's (it said m.yaml:2, the scene: line).
  EXPECT_NE(late.err.find("m.yaml:3: goldens[0].times[1]: 9 s is past the scene's duration (5 s)"), std::string::npos)
      << late.err;
  // An entry's own dt is bounded as the scene file's is, over the run to its latest still.
  write(dir + "/m.yaml", "goldens:\n  - scene: d.yaml\n    dt: 1e-12\n    times: [1]\n");
  const CliResult tiny = run_clothsim({"golden", "update", dir + "/m.yaml"});
  EXPECT_EQ(tiny.exit_code, 2);
  EXPECT_EQ(line_count(tiny.err), 1) << tiny.err;
  EXPECT_NE(tiny.err.find("m.yaml:3: goldens[0].dt: duration / dt = 1 s / 1e-12 s = 1e+12 steps, more than the limit"),
            std::string::npos)
      << tiny.err;
  // An unclosed '[' is named at its own line, not where yaml-cpp gave up (the line after).
  write(dir + "/m.yaml", "goldens:\n  - scene: d.yaml\n    times: [1, 2\n    dt: 1e-4\n");
  const CliResult open = run_clothsim({"golden", "update", dir + "/m.yaml"});
  EXPECT_EQ(open.exit_code, 2);
  EXPECT_NE(open.err.find("m.yaml:3: invalid YAML: end of sequence flow not found"), std::string::npos) << open.err;
  EXPECT_TRUE(only_files(dir, {"m.yaml", "d.yaml"})) << "nothing rendered";
}

// A name is a name (scene/names.h): "goldens.yaml\0" once cut the image path at the NUL and
// wrote a PNG over the manifest itself.
TEST(CmdGolden, AHostileNameIsRefusedAndOverwritesNothing) {
  UserProject p("golden_hostile_name");
  for (const char* name : {"goldens.yaml\\0", "my_drape.yaml\\0", "../escaped", "a\\x1b[2Jb", "x\\u202Ey"}) {
    write(p.manifest, std::string("size: [160, 90]\ngoldens:\n  - scene: my_drape.yaml\n    times: [0.05]\n    name: \"") + name + "\"\n");
    const std::string before = slurp(p.manifest), scene = slurp(p.scene);
    const CliResult r = run_clothsim({"golden", "update", p.manifest});
    EXPECT_EQ(r.exit_code, 2) << name;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("goldens.yaml:5: goldens[0].name: holds"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(p.manifest), before);
    EXPECT_EQ(slurp(p.scene), scene);
    EXPECT_TRUE(only_files(p.dir, {"my_drape.yaml", "goldens.yaml"}));
  }
}

// --max-memory as run and compare have it: every entry's run is estimated before anything is
// rendered, and one over the limit is refused (exit 2) naming its line and the estimate.
TEST(CmdGolden, AnEntryOverMaxMemoryIsRefusedBeforeAnythingIsRendered) {
  UserProject p("golden_max_memory");
  // The first entry fits in 500 MB (about 170 MB); the second, at 4000 x 4000, needs over 1 GB.
  write(p.manifest,
        "size: [160, 90]\ngoldens:\n  - scene: my_drape.yaml\n    times: [0.05]\n"
        "  - scene: my_drape.yaml\n    name: big\n    size: [4000, 4000]\n    times: [0.05]\n");
  const std::string failures = p.dir + "/failures";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"golden", "check", p.manifest, "--max-memory", "500M", "--failures", failures},
        std::vector<std::string>{"golden", "update", p.manifest, "--max-memory", "500M"}}) {
    const CliResult r = run_clothsim(args);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("clothsim: " + p.manifest + ":5: goldens[1] (" + p.dir + "/my_drape.yaml): needs an estimated ",
                          0),
              0u)
        << r.err;
    EXPECT_NE(r.err.find("renderer 4000x4000"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("more than --max-memory 500 MB"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << "nothing rendered, not even the first entry";
    EXPECT_TRUE(only_files(p.dir, {"my_drape.yaml", "goldens.yaml"})) << "nothing written";
  }
  // Within the limit, the same entries are rendered.
  write(p.manifest, "size: [160, 90]\ngoldens:\n  - scene: my_drape.yaml\n    times: [0.05]\n");
  const CliResult fits = run_clothsim({"golden", "update", p.manifest, "--max-memory", "500M"});
  EXPECT_EQ(fits.exit_code, 0) << fits.err;
  EXPECT_TRUE(fs::exists(p.dir + "/my_drape_t50ms.png"));
  const CliResult bad = run_clothsim({"golden", "check", p.manifest, "--max-memory", "lots"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--max-memory: 'lots' is not a size"), std::string::npos) << bad.err;
}

TEST(CmdGolden, AnOutputOntoTheManifestASceneOrAGoldenImageIsRefused) {
  UserProject p("golden_onto_input");
  ASSERT_EQ(run_clothsim({"golden", "update", p.manifest}).exit_code, 0);
  fs::create_symlink(p.scene, p.dir + "/scene_link.yaml");
  const std::string manifest = slurp(p.manifest), scene = slurp(p.scene), golden = slurp(p.golden);
  for (const std::string& out : {p.manifest, p.dir + "/scene_link.yaml", p.dir + "/./my_drape_t200ms.png"}) {
    const CliResult r = run_clothsim({"golden", "check", p.manifest, "--csv", out});
    EXPECT_EQ(r.exit_code, 2) << out;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("an output never replaces an input"), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(p.manifest), manifest);
  EXPECT_EQ(slurp(p.scene), scene);
  EXPECT_EQ(slurp(p.golden), golden);
}

TEST(CmdGolden, ANameTooLongForTheFileSystemIsRefusedBeforeAnyRender) {
  UserProject p("golden_long_name");
  write(p.manifest, "size: [160, 90]\ngoldens:\n  - scene: my_drape.yaml\n    times: [0.05]\n    name: " +
                        std::string(300, 'n') + "\n");
  const CliResult r = run_clothsim({"golden", "update", p.manifest});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("goldens[0].name: too long"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "") << "nothing rendered";
  EXPECT_TRUE(only_files(p.dir, {"my_drape.yaml", "goldens.yaml"}));
}

}  // namespace
}  // namespace clothsim::testing
