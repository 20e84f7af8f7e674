// The shard journal: what is recorded survives a new process (a requeue), nothing is left
// half-written, and each record call leaves one log line.
#include "study/journal.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

namespace clothsim::analysis {
namespace {

namespace fs = std::filesystem;

std::string fresh_dir(const std::string& name) {
  const fs::path dir = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / name;
  fs::remove_all(dir);
  return dir.string();
}

TEST(Journal, KeepsRecordedItemsForTheNextProcess) {
  const std::string dir = fresh_dir("journal_reopen");
  {
    Journal j(dir);
    EXPECT_FALSE(j.done(3));
    j.record(3, "a,b\n");
    j.record(10, "c,d\n");
  }
  Journal again(dir);
  EXPECT_TRUE(again.done(3));
  EXPECT_TRUE(again.done(10));
  EXPECT_FALSE(again.done(4));
  EXPECT_EQ(again.size(), 2u);
  const auto items = Journal::read_items(dir);
  EXPECT_EQ(items.at(3), "a,b\n");
  EXPECT_EQ(items.at(10), "c,d\n");
}

TEST(Journal, KeepsEachItemsSummaryLaneBesideItsRow) {
  const std::string dir = fresh_dir("journal_lanes");
  {
    Journal j(dir);
    j.record(2, "a,b\n", "{\n  \"x\": 1\n}");
    j.record(5, "c,d\n");  // no lane
  }
  const auto lanes = Journal::read_lanes(dir);
  ASSERT_EQ(lanes.size(), 1u);
  EXPECT_EQ(lanes.at(2), "{\n  \"x\": 1\n}");
  EXPECT_EQ(Journal::read_items(dir).size(), 2u);
}

TEST(Journal, IgnoresTemporariesLeftByAKilledWriter) {
  const std::string dir = fresh_dir("journal_temporaries");
  Journal j(dir);
  std::ofstream(dir + "/items/.7.tmp-123-4") << "half a ro";  // what SIGKILL mid-write leaves
  EXPECT_TRUE(Journal::read_items(dir).empty());
  EXPECT_FALSE(Journal(dir).done(7));
}

// A process id that no longer exists: a child that has exited and been reaped.
pid_t dead_pid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  int status = 0;
  waitpid(child, &status, 0);
  return child;
}

TEST(Journal, ARerunRemovesTemporariesOfAKilledWriter) {
  const std::string dir = fresh_dir("journal_stale_temporaries");
  { Journal j(dir); }
  const std::string dead = std::to_string(dead_pid()), alive = std::to_string(getppid());
  for (const std::string& f : {"/items/.7.tmp-" + dead + "-4", "/lanes/.7.tmp-" + dead + "-9", "/.provenance.tmp-" + dead + "-1",
                               "/items/.8.tmp-" + alive + "-2"})
    std::ofstream(dir + f) << "x";
  Journal again(dir);
  EXPECT_FALSE(fs::exists(dir + "/items/.7.tmp-" + dead + "-4"));
  EXPECT_FALSE(fs::exists(dir + "/lanes/.7.tmp-" + dead + "-9"));
  EXPECT_FALSE(fs::exists(dir + "/.provenance.tmp-" + dead + "-1"));
  EXPECT_TRUE(fs::exists(dir + "/items/.8.tmp-" + alive + "-2")) << "a live writer's temporary stays";
}

TEST(Journal, ARerunRedoesAnItemCutShort) {
  const std::string dir = fresh_dir("journal_cut_rerun");
  {
    Journal j(dir);
    j.record(3, "a,b\nc,d\n");
    j.record(4, "e,f\n");
  }
  const std::string item = dir + "/items/3";
  fs::resize_file(item, 4);  // cut at a row's end: one row of two
  Journal again(dir);
  EXPECT_FALSE(again.done(3));
  EXPECT_TRUE(again.done(4));
  EXPECT_FALSE(fs::exists(item));
}

TEST(Journal, ReadingRefusesAnItemOrLaneCutShortNamingIt) {
  const std::string dir = fresh_dir("journal_cut_read");
  {
    Journal j(dir);
    j.record(3, "a,b\nc,d\n", "{\"x\": 1}");
  }
  for (const std::string folder : {"items", "lanes"}) {
    const std::string path = dir + "/" + folder + "/3";
    const std::string whole = read_whole_file(path);
    for (std::size_t cut : {whole.size() - 1, whole.size() - 3, std::size_t{4}, std::size_t{0}}) {
      std::ofstream(path, std::ios::trunc) << whole.substr(0, cut);
      try {
        folder == std::string("items") ? Journal::read_items(dir) : Journal::read_lanes(dir);
        ADD_FAILURE() << path << " cut at " << cut << " was read";
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path + ": damaged"), std::string::npos) << e.what();
      }
    }
    std::ofstream(path, std::ios::trunc) << whole;
  }
}

TEST(Journal, AKilledWriterLeavesNoTemporaryBehind) {
  const std::string dir = fresh_dir("journal_killed_clean");
  { Journal j(dir); }
  for (int trial = 0; trial < 5; ++trial) {
    const pid_t child = fork();
    if (child == 0) {
      Journal j(dir);
      for (std::size_t i = 0;; ++i) j.record(1000 * trial + i % 1000, std::string(100000, 'x') + "\n");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20 + 7 * trial));
    kill(child, SIGKILL);
    int status = 0;
    waitpid(child, &status, 0);
  }
  Journal again(dir);  // the rerun: whatever the kills left between naming and renaming goes
  for (const char* folder : {"items", "lanes"})
    for (const auto& e : fs::directory_iterator(dir + "/" + folder))
      EXPECT_NE(e.path().filename().string().front(), '.') << e.path();
}

TEST(Journal, RecordsFromManyThreadsEachOnce) {
  const std::string dir = fresh_dir("journal_threads");
  Journal j(dir);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&j, t] {
      for (int i = 0; i < 25; ++i) j.record(static_cast<std::size_t>(t * 25 + i), std::to_string(i) + "\n");
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(Journal::read_items(dir).size(), 100u);
  std::ifstream log(dir + "/log");
  std::vector<int> seen(100, 0);
  for (int item; log >> item;) ++seen.at(static_cast<std::size_t>(item));
  for (int count : seen) EXPECT_EQ(count, 1);
}

TEST(Journal, SurvivesAProcessKilledBetweenRecords) {
  const std::string dir = fresh_dir("journal_killed");
  fs::create_directories(dir + "/items");
  const pid_t child = fork();
  if (child == 0) {
    Journal j(dir);
    for (std::size_t i = 0; i < 2000; ++i) j.record(i, std::string(1000, 'x') + "\n");  // until killed
    _exit(0);
  }
  while (std::distance(fs::directory_iterator(dir + "/items"), fs::directory_iterator()) < 5)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  for (const auto& [item, payload] : Journal::read_items(dir)) EXPECT_EQ(payload.size(), 1001u) << "item " << item;
}

TEST(Journal, WritesFilesWholeOrNotAtAll) {
  const std::string dir = fresh_dir("journal_atomic");
  fs::create_directories(dir);
  write_file_atomically(dir + "/f", "one");
  write_file_atomically(dir + "/f", "two");
  EXPECT_EQ(read_whole_file(dir + "/f"), "two");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  EXPECT_THROW(write_file_atomically(dir + "/no/such/dir/f", "x"), std::runtime_error);
}

}  // namespace
}  // namespace clothsim::analysis
