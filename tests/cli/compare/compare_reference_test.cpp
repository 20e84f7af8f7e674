// compare's reference and its own error (study/reference.h): on a smooth scene (the barrier
// drape) the error colouring's reference is the adaptive pair, and every error printed comes with
// its estimated error, in the table, the summary's reference.estimated_error_m and each lane's
// unresolved flag; a lane under 10x the reference's error is unresolved, not a number. On a
// scene with projected contacts the reference is fixed-step RK4, checked by a run at twice its
// step.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/cli_process.h"

namespace ct = clothsim::testing;

namespace {

const std::string kSmooth = std::string(CLOTHSIM_SCENES_DIR) + "/drape_smooth.yaml";

// The barrier drape at 9 x 9 over 0.2 s, its error measured at the last frame (no pictures).
ct::CliResult compare_smooth(const std::string& integrators, const std::string& summary) {
  return ct::run_clothsim({"compare", kSmooth, "--set", "cloth.particles=[9,9]", "--duration", "0.2", "--integrators",
                           integrators, "--color", "error", "--summary", summary});
}

// The JSON object around `key`'s first occurrence after `from`.
std::string object_at(const std::string& json, const std::string& key, std::size_t from = 0) {
  const std::size_t at = json.find(key, from);
  if (at == std::string::npos) return "";
  const std::size_t open = json.rfind('{', at);
  return json.substr(open, json.find('}', at) - open);
}

TEST(CompareReference, OnASmoothSceneTheReferenceIsAdaptiveAndStatesItsEstimatedError) {
  const std::string dir = ct::scratch_dir("compare_reference_smooth");
  const auto r = compare_smooth("symplectic_euler@1e-4,midpoint@2e-4", dir + "/s.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("dopri5 adaptive (reference)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error against the adaptive reference: largest"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reference: dopri5 adaptive at tolerance 1e-07, checked by a solve at 1e-08: estimated error"),
            std::string::npos)
      << r.out;
  const std::string json = ct::slurp(dir + "/s.json");
  const std::string reference = object_at(json, "\"estimated_error_m\"");
  ASSERT_FALSE(reference.empty()) << json;
  const double estimate = std::stod(reference.substr(reference.find(':', reference.find("estimated_error_m")) + 1));
  EXPECT_GT(estimate, 0.0) << reference;
  EXPECT_LT(estimate, 1e-7) << "far below any lane's error" << reference;
  EXPECT_NE(object_at(json, "\"lane\": \"midpoint@2e-4\"").find("\"unresolved\": false"), std::string::npos) << json;
  // Its lane row says what ran (#51: it read "rk4" at the fixed-step reference's 3.125e-6 s).
  const std::string row = object_at(json, "\"role\": \"reference\"");
  EXPECT_NE(row.find("\"integrator\": \"dopri5\""), std::string::npos) << row;
  EXPECT_NE(row.find("\"dt\": null"), std::string::npos) << row;
  EXPECT_NE(row.find("\"tolerance\": 9.9999999999999995e-08"), std::string::npos) << row;
  EXPECT_NE(row.find("\"check_tolerance\": 1e-08"), std::string::npos) << row;
}

TEST(CompareReference, ALaneUnderTenTimesTheReferencesErrorIsUnresolvedNotANumber) {
  // RK4 at 1e-5 s on the cloth is at round-off, far under the reference's estimate.
  const std::string dir = ct::scratch_dir("compare_reference_unresolved");
  const auto r = compare_smooth("rk4@1e-5,symplectic_euler@1e-4", dir + "/s.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t line = r.out.find("rk4 @ 1e-5 s: error against the adaptive reference:");
  ASSERT_NE(line, std::string::npos) << r.out;
  const std::string text = r.out.substr(line, r.out.find('\n', line) - line);
  EXPECT_NE(text.find("unresolved: under 10 x the reference's estimated error"), std::string::npos) << text;
  EXPECT_EQ(text.find("largest"), std::string::npos) << "no number for it: " << text;
  const std::string json = ct::slurp(dir + "/s.json");
  EXPECT_NE(object_at(json, "\"lane\": \"rk4@1e-5\"").find("\"unresolved\": true"), std::string::npos) << json;
  EXPECT_NE(object_at(json, "\"lane\": \"symplectic_euler@1e-4\"").find("\"unresolved\": false"), std::string::npos)
      << json;
}

TEST(CompareReference, ASceneWithProjectedContactsKeepsTheFixedStepRk4Reference) {
  const std::string dir = ct::scratch_dir("compare_reference_projection");
  const auto r = ct::run_clothsim({"compare", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--set",
                                   "cloth.particles=[9,9]", "--duration", "0.2", "--integrators", "symplectic_euler",
                                   "--color", "error", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rk4 (reference)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("dopri5"), std::string::npos) << r.out;
  // Its own error comes with it too: a run at twice its step (1e-4 / 4 = 2.5e-5 s, so 5e-5 s).
  EXPECT_NE(r.out.find("reference: rk4 @ 2.5e-05 s, checked by a run at twice its step (5e-05 s): estimated error"),
            std::string::npos)
      << r.out;
  const std::string json = ct::slurp(dir + "/s.json");
  const std::string reference = object_at(json, "\"estimated_error_m\"");
  EXPECT_NE(reference.find("\"check_dt\": 5.0000000000000002e-05"), std::string::npos) << reference;
  const double estimate = std::stod(reference.substr(reference.find(':', reference.find("estimated_error_m")) + 1));
  EXPECT_GT(estimate, 0.0) << "contact makes the two runs differ" << reference;
  EXPECT_LT(estimate, 1e-3) << "well under the lane's error at 1e-4 s" << reference;
}

// The largest error `json`'s lane object around `key` states.
double field_max_at(const std::string& json, const std::string& key) {
  const std::string lane = object_at(json, key);
  const std::size_t at = lane.find("\"field_max\":");
  return at == std::string::npos ? -1.0 : std::stod(lane.substr(at + 12));
}

TEST(CompareReference, VaryMeasuresEachValueAgainstItsOwnScenesReference) {
  // --vary collision.model=projection,barrier: each value is its own scene, so each gets the
  // reference a comparison of that scene alone would (fixed-step RK4 under projection, the
  // adaptive solve on the barrier), and its lanes' errors are the same numbers to the bit.
  const std::string dir = ct::scratch_dir("compare_reference_vary");
  const std::vector<std::string> small{"--set", "cloth.particles=[9,9]", "--duration", "0.2", "--integrators",
                                       "symplectic_euler@1e-4", "--color", "error"};
  std::vector<std::string> vary{"compare", kSmooth, "--vary", "collision.model=projection,barrier", "--summary",
                                dir + "/vary.json"};
  vary.insert(vary.end(), small.begin(), small.end());
  const auto r = ct::run_clothsim(vary);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rk4 (reference, collision.model = projection)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("dopri5 adaptive (reference, collision.model = barrier)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reference for collision.model = barrier: dopri5 adaptive at tolerance 1e-07"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("reference for collision.model = projection: rk4 @ 2.5e-05 s, checked by a run at twice"),
            std::string::npos)
      << r.out;
  const std::string json = ct::slurp(dir + "/vary.json");
  EXPECT_NE(json.find("\"references\": ["), std::string::npos) << json;
  EXPECT_NE(json.find("\"for\": \"collision.model = barrier\""), std::string::npos) << json;
  for (const std::string model : {"projection", "barrier"}) {
    std::vector<std::string> alone{"compare", kSmooth, "--set", "collision.model=" + model, "--summary",
                                   dir + "/" + model + ".json"};
    alone.insert(alone.end(), small.begin(), small.end());
    const auto a = ct::run_clothsim(alone);
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const double by_itself = field_max_at(ct::slurp(dir + "/" + model + ".json"), "\"lane\": \"symplectic_euler@1e-4\"");
    ASSERT_GT(by_itself, 0.0);
    EXPECT_EQ(field_max_at(json, "\"name\": \"symplectic_euler, collision.model = " + model + "\""), by_itself) << model;
  }
}


// The reference cache (study/reference_cache.h), through the CLI: a cache folder of the test's
// own, switched on (the test environment turns it off for every other test).
ct::CliResult compare_cached(const std::string& cache, const std::vector<std::string>& extra) {
  std::vector<std::string> args{"compare", kSmooth, "--set", "cloth.particles=[9,9]", "--duration", "0.3",
                                "--integrators", "symplectic_euler@1e-4,midpoint@2e-4", "--width", "320",
                                "--height", "180", "--preset", "ultrafast"};
  args.insert(args.end(), extra.begin(), extra.end());
  return ct::run_clothsim(args, "env -u CLOTHSIM_REFERENCE_CACHE_MAX XDG_CACHE_HOME=" + ct::shell_quote(cache));
}

std::string cache_of(const std::string& json) {
  const std::string reference = object_at(json, "\"estimated_error_m\"");
  const std::size_t at = reference.find("\"cache\": \"");
  return at == std::string::npos ? "" : reference.substr(at + 10, reference.find('"', at + 10) - at - 10);
}

TEST(CompareReference, ARerunReusesTheCachedReferenceAndWritesTheSameBytes) {
  const std::string dir = ct::scratch_dir("compare_reference_cache");
  const std::string cache = dir + "/xdg";
  const auto first = compare_cached(cache, {"--video", dir + "/a.mp4", "--summary", dir + "/a.json"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(cache_of(ct::slurp(dir + "/a.json")), "computed");
  EXPECT_NE(first.out.find("reference: computed, and stored in the cache (" + cache + "/clothsim/"), std::string::npos)
      << first.out;
  const auto second = compare_cached(cache, {"--video", dir + "/b.mp4", "--summary", dir + "/b.json"});
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(cache_of(ct::slurp(dir + "/b.json")), "reused");
  EXPECT_NE(second.out.find("reference: reused from the cache ("), std::string::npos) << second.out;
  EXPECT_EQ(ct::slurp(dir + "/a.mp4"), ct::slurp(dir + "/b.mp4")) << "the clip, byte for byte";
  // The same errors in the summary.
  const std::string a = ct::slurp(dir + "/a.json"), b = ct::slurp(dir + "/b.json");
  EXPECT_EQ(field_max_at(a, "\"lane\": \"midpoint@2e-4\""), field_max_at(b, "\"lane\": \"midpoint@2e-4\""));
}

TEST(CompareReference, AChangedSetMissesAndNoReferenceCacheBypasses) {
  const std::string dir = ct::scratch_dir("compare_reference_cache_miss");
  const std::string cache = dir + "/xdg";
  ASSERT_EQ(compare_cached(cache, {"--summary", dir + "/a.json", "--color", "error"}).exit_code, 0);
  EXPECT_EQ(cache_of(ct::slurp(dir + "/a.json")), "computed");
  const auto stiffer = compare_cached(cache, {"--summary", dir + "/b.json", "--color", "error", "--set",
                                              "cloth.springs.structural.stiffness=21000"});
  ASSERT_EQ(stiffer.exit_code, 0) << stiffer.err;
  EXPECT_EQ(cache_of(ct::slurp(dir + "/b.json")), "computed") << "another scene, another reference";
  const auto bypass = compare_cached(cache, {"--summary", dir + "/c.json", "--color", "error", "--no-reference-cache"});
  ASSERT_EQ(bypass.exit_code, 0) << bypass.err;
  EXPECT_EQ(cache_of(ct::slurp(dir + "/c.json")), "computed");
  EXPECT_NE(bypass.out.find("reference: computed (the cache is off"), std::string::npos) << bypass.out;
  const auto info = ct::run_clothsim({"cache", "info"}, "env XDG_CACHE_HOME=" + ct::shell_quote(cache));
  EXPECT_NE(info.out.find("holds 2 entries"), std::string::npos) << info.out;
  const auto clear = ct::run_clothsim({"cache", "clear"}, "env XDG_CACHE_HOME=" + ct::shell_quote(cache));
  EXPECT_NE(clear.out.find("removed 2 entries"), std::string::npos) << clear.out;
  ASSERT_EQ(compare_cached(cache, {"--summary", dir + "/d.json", "--color", "error"}).exit_code, 0);
  EXPECT_EQ(cache_of(ct::slurp(dir + "/d.json")), "computed") << "cleared";
  const auto bad = ct::run_clothsim({"compare", kSmooth, "--summary", dir + "/e.json"},
                                    "env CLOTHSIM_REFERENCE_CACHE_MAX=lots");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("CLOTHSIM_REFERENCE_CACHE_MAX: 'lots' is not a size"), std::string::npos) << bad.err;
}

}  // namespace
