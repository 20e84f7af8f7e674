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
