// FrameSink writing frame_00000.png, frame_00001.png ... PNG encoding (deflate) costs about
// as much as rendering a frame, so it runs on a background thread: add() queues a copy of
// the frame and returns; a short queue keeps memory flat however long the clip. A failed
// write is reported by the next add() or by finish(), naming the file.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "frame_sink.h"
#include "clip/common/cli_common.h"

namespace clothsim::clip {

namespace {

constexpr std::size_t kMaxQueued = 3;  // frames waiting for the writer; add() blocks beyond this
// zlib level 1: at 720p writing a frame takes as long as rendering one, so speed beats a few
// per cent of file size (BENCHMARKS.md, "Renderer and PNG").
constexpr int kZlibLevel = 1;

class PngSequenceSink final : public FrameSink {
 public:
  PngSequenceSink(std::string dir, PngText meta) : dir_(std::move(dir)), meta_(std::move(meta)) {
    std::error_code ec;
    created_ = !std::filesystem::exists(dir_, ec);
    ensure_directory(dir_, "--frames");  // fail before any simulation, not at the first frame
    refuse_existing_frames(dir_, "--frames");
    writer_ = std::thread([this] { write_loop(); });
  }

  ~PngSequenceSink() override { abandon(); }

  void abandon() override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      abandoned_ = true;  // not finished: drop what is queued (each file on disk is whole)
      queue_.clear();
    }
    ready_.notify_all();
    if (writer_.joinable()) writer_.join();  // at most the PNG being written finishes
    if (written_ == 0 && created_) {
      // Nothing in it: a directory this sink made goes too (a failed compare left one per lane).
      std::error_code ec;
      std::filesystem::remove(dir_, ec);
    }
  }

  // Every PNG written is complete (written under its name only when whole), so all of them stay.
  std::string written() const override {
    const long n = written_;
    if (n == 0 || !std::filesystem::is_directory(dir_)) return "";  // removed meanwhile: nothing kept
    return std::to_string(n) + (n == 1 ? " PNG in " : " PNGs in ") + dir_;
  }

  void add(int index, double t, const Image& frame) override {
    std::unique_lock<std::mutex> lock(mutex_);
    space_.wait(lock, [this] { return queue_.size() < kMaxQueued || !error_.empty(); });
    if (!error_.empty()) throw RuntimeFailure(error_);
    queue_.push_back(Job{index, t, frame});
    lock.unlock();
    ready_.notify_one();
  }

  void finish() override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      finishing_ = true;
    }
    ready_.notify_all();
    if (writer_.joinable()) writer_.join();  // every queued frame written (or the first error)
    if (!error_.empty()) throw RuntimeFailure(error_);
    remove_later_frames();
  }

 private:
  struct Job {
    int index;
    double t;
    Image frame;
  };

  // A longer earlier run's frames past this run's last would read as its continuation (encode
  // takes every frame of an unbroken sequence): gone once this sequence is complete.
  void remove_later_frames() const {
    std::error_code ec;
    std::vector<std::filesystem::path> later;
    for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.size() != 15 || name.compare(0, 6, "frame_") != 0 || name.compare(11, 4, ".png") != 0 ||
          name.find_first_not_of("0123456789", 6) != 11)
        continue;
      if (std::stoi(name.substr(6, 5)) > last_index_) later.push_back(entry.path());
    }
    for (const auto& path : later) std::filesystem::remove(path, ec);
  }

  void write_loop() {
    for (;;) {
      std::unique_lock<std::mutex> lock(mutex_);
      ready_.wait(lock, [this] { return !queue_.empty() || finishing_ || abandoned_; });
      if (abandoned_ || queue_.empty()) return;  // abandoned, or finishing with nothing left
      Job job = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      space_.notify_one();

      char name[32], time[32];
      std::snprintf(name, sizeof name, "frame_%05d.png", job.index);
      std::snprintf(time, sizeof time, "%.9g", job.t);
      PngText text = meta_;
      text.emplace_back("t", time);
      try {
        write_png(dir_ + "/" + name, job.frame, text, kZlibLevel, Replace::kUnlinkFirst);  // no hidden link to leave
        ++written_;
        last_index_ = std::max(last_index_, job.index);
      } catch (const PngError& e) {
        lock.lock();
        error_ = e.what();  // "cannot write DIR/frame_00012.png: No space left on device"
        queue_.clear();
        lock.unlock();
        space_.notify_all();
        return;
      }
    }
  }

  const std::string dir_;
  const PngText meta_;
  std::mutex mutex_;
  std::condition_variable ready_;  // writer: a job, finish or abandon
  std::condition_variable space_;  // add(): room in the queue, or an error
  std::deque<Job> queue_;
  bool finishing_ = false, abandoned_ = false;
  bool created_ = false;  // the directory did not exist before this sink
  std::string error_;              // first failure; guarded by mutex_ until the writer has joined
  std::atomic<long> written_{0};   // PNGs on disk, counted by the writer
  int last_index_ = -1;            // the largest frame written; read after the writer has joined
  std::thread writer_;
};

}  // namespace

std::unique_ptr<FrameSink> make_png_sequence_sink(const std::string& dir, PngText meta) {
  return std::make_unique<PngSequenceSink>(dir, std::move(meta));
}

}  // namespace clothsim::clip
