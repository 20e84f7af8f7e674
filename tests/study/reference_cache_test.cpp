// The reference cache (study/reference_cache.h): what is stored is served whole or not at all
// (a truncated, damaged or foreign entry is removed, never served), the folder stays within its
// cap, writers of one key racing each other leave one whole entry, and the key follows the
// scene's content.
#include "study/reference_cache.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "test_support.h"

namespace clothsim::analysis {
namespace {

namespace fs = std::filesystem;
using testing::scene_path;

ReferenceCache fresh(const std::string& name, std::uint64_t max_bytes = 1ull << 30) {
  const std::string dir = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/" + name;
  fs::remove_all(dir);
  return ReferenceCache({dir, max_bytes});
}

std::string payload(std::size_t n, char seed) {
  std::string s(n, '\0');
  for (std::size_t i = 0; i < n; ++i) s[i] = static_cast<char>(seed + 31 * i);
  return s;
}

TEST(ReferenceCache, ServesWhatWasStoredUnderItsKeyOnly) {
  const ReferenceCache cache = fresh("cache_hit");
  EXPECT_FALSE(cache.load("a")) << "an empty cache";
  ASSERT_TRUE(cache.store("a", payload(5000, 1)));
  EXPECT_EQ(cache.load("a"), payload(5000, 1));
  EXPECT_FALSE(cache.load("b"));
  EXPECT_EQ(cache.contents().entries, 1);
}

TEST(ReferenceCache, ATruncatedOrDamagedEntryIsRemovedNotServed) {
  const ReferenceCache cache = fresh("cache_damaged");
  ASSERT_TRUE(cache.store("k", payload(5000, 2)));
  const std::string path = cache.path_of("k");
  fs::resize_file(path, fs::file_size(path) - 1);
  EXPECT_FALSE(cache.load("k")) << "truncated";
  EXPECT_FALSE(fs::exists(path)) << "and removed, to be recomputed";

  ASSERT_TRUE(cache.store("k", payload(5000, 2)));
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-7, std::ios::end);
    f.put('\x7f');
  }
  EXPECT_FALSE(cache.load("k")) << "a byte of the payload changed: the checksum says so";
  EXPECT_FALSE(fs::exists(path));

  ASSERT_TRUE(cache.store("k", payload(5000, 2)));
  std::ofstream(path, std::ios::app) << "x";
  EXPECT_FALSE(cache.load("k")) << "longer than it says";

  // Another key's entry under this key's name (a digest collision): not served.
  ASSERT_TRUE(cache.store("other", payload(100, 3)));
  fs::rename(cache.path_of("other"), path);
  EXPECT_FALSE(cache.load("k"));
}

TEST(ReferenceCache, KeepsWithinItsCapByRemovingTheLeastRecentlyUsed) {
  // Entries of about 40 kB under a 100 kB cap: the third stored evicts the one least used.
  const ReferenceCache cache = fresh("cache_cap", 100'000);
  ASSERT_TRUE(cache.store("first", payload(40'000, 1)));
  ASSERT_TRUE(cache.store("second", payload(40'000, 2)));
  // "first" used after "second" was stored: "second" is now the least recently used.
  fs::last_write_time(cache.path_of("second"), fs::last_write_time(cache.path_of("first")) - std::chrono::seconds(10));
  ASSERT_TRUE(cache.load("first"));
  ASSERT_TRUE(cache.store("third", payload(40'000, 3)));
  EXPECT_LE(cache.contents().bytes, 100'000u);
  EXPECT_TRUE(cache.load("first"));
  EXPECT_FALSE(cache.load("second"));
  EXPECT_TRUE(cache.load("third"));
  EXPECT_FALSE(cache.store("huge", payload(200'000, 4))) << "larger than the cap: not kept";
  EXPECT_FALSE(cache.load("huge"));
}

TEST(ReferenceCache, WritersOfOneKeyRacingLeaveOneWholeEntryAndReadersSeeWholeOnes) {
  const ReferenceCache cache = fresh("cache_race");
  const std::string data = payload(2'000'000, 5);
  std::vector<std::thread> threads;
  std::atomic<int> partial{0};
  for (int w = 0; w < 4; ++w) threads.emplace_back([&] { EXPECT_TRUE(cache.store("same", data)); });
  for (int r = 0; r < 2; ++r)
    threads.emplace_back([&] {
      for (int k = 0; k < 20; ++k)
        if (const auto got = cache.load("same"); got && *got != data) ++partial;
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(partial, 0);
  EXPECT_EQ(cache.load("same"), data);
  EXPECT_EQ(cache.contents().entries, 1);
}

TEST(ReferenceCache, ClearRemovesEveryEntry) {
  const ReferenceCache cache = fresh("cache_clear");
  ASSERT_TRUE(cache.store("a", payload(10, 1)));
  ASSERT_TRUE(cache.store("b", payload(10, 2)));
  std::ofstream(cache.dir() + "/notes.txt") << "not ours";
  EXPECT_EQ(cache.clear().entries, 2);
  EXPECT_EQ(cache.contents().entries, 0);
  EXPECT_TRUE(fs::exists(cache.dir() + "/notes.txt")) << "what is not an entry stays";
}

TEST(ReferenceCache, TheModelsDigestFollowsItsContentNotItsText) {
  const std::string path = scene_path("drape_smooth.yaml");
  const std::string base = model_digest(build_model(load_scene(path, {})));
  EXPECT_EQ(model_digest(build_model(load_scene(path, {}))), base);
  EXPECT_EQ(model_digest(build_model(load_scene(path, {"name=renamed"}))), base) << "a name moves nothing";
  EXPECT_EQ(model_digest(build_model(load_scene(path, {"cloth.springs.structural.stiffness=20000.0"}))), base)
      << "the same value spelt otherwise";
  for (const char* set : {"cloth.springs.structural.stiffness=20001", "air_drag=3.5e-4", "cloth.particles=[13,13]",
                          "collision.barrier_stiffness=2e6", "gravity=[0,-9.81,0]",
                          "spheres.0.motion.0.velocity=[0,0,4]"})
    EXPECT_NE(model_digest(build_model(load_scene(path, {set}))), base) << set;
}

TEST(ReferenceCache, SettingsComeFromTheEnvironment) {
  EXPECT_EQ(parse_cache_size("1G"), 1ull << 30);
  EXPECT_EQ(parse_cache_size("512M"), 512ull << 20);
  EXPECT_EQ(parse_cache_size("1000"), 1000u);
  EXPECT_EQ(parse_cache_size("0"), 0u);
  EXPECT_FALSE(parse_cache_size("1T"));
  EXPECT_FALSE(parse_cache_size("-1"));
  EXPECT_FALSE(parse_cache_size("big"));
  ::setenv("XDG_CACHE_HOME", "/tmp/xdg-test-cache", 1);
  EXPECT_EQ(reference_cache_settings().dir, "/tmp/xdg-test-cache/clothsim");
  ::setenv("CLOTHSIM_REFERENCE_CACHE_MAX", "0", 1);
  EXPECT_FALSE(ReferenceCache(reference_cache_settings()).enabled()) << "0 turns it off";
  ::setenv("CLOTHSIM_REFERENCE_CACHE_MAX", "lots", 1);
  EXPECT_THROW(reference_cache_settings(), std::invalid_argument);
  ::unsetenv("CLOTHSIM_REFERENCE_CACHE_MAX");
}

}  // namespace
}  // namespace clothsim::analysis
