// A shard's journal: one file per finished work item, so a shard stopped at any instant
// (SIGTERM then SIGKILL at a Slurm time limit, a node failure, `scontrol requeue`) keeps
// every item it finished, and a rerun skips them.
//
// Each item is written to a nameless file, named and renamed into place, so an item file is
// whole or absent, never half-written, whatever kills the process; a rerun removes the hidden
// temporaries a SIGKILL can leave between naming and renaming. Each item and lane file ends
// with a mark giving its length: a file cut short afterwards is redone by a rerun and refused
// by merge (read_items, read_lanes throw naming it). A log line per recorded
// item (appended, one write each) lets a test check that no finished item ran twice.
//
// Layout of DIR: provenance (shard.h's record), items/ITEM (the item's payload, a CSV row),
// lanes/ITEM (optional: the item's --summary lane, JSON, written before items/ITEM so a
// finished item has it), log ("ITEM\n" per record call, in the order they finished).
#pragma once

#include <cstddef>
#include <map>
#include <mutex>
#include <string>

namespace clothsim::analysis {

class Journal {
 public:
  // Opens DIR, creating it and DIR/items when absent. Throws std::runtime_error naming DIR.
  explicit Journal(std::string dir);
  bool done(std::size_t item) const;
  std::size_t size() const;
  // Writes the item's payload (and its lane, when not empty) atomically; safe from several
  // threads at once.
  void record(std::size_t item, const std::string& payload, const std::string& lane = "");
  const std::string& dir() const { return dir_; }

  // Every finished item's payload, by item. Throws std::runtime_error naming a damaged file.
  static std::map<std::size_t, std::string> read_items(const std::string& dir);
  // Every finished item's lane, by item (items recorded without one are absent).
  static std::map<std::size_t, std::string> read_lanes(const std::string& dir);

 private:
  std::string dir_;
  std::map<std::size_t, std::string> items_;
  mutable std::mutex mutex_;
};

// Writes `text` to PATH through a temporary file in the same folder and a rename.
// Throws std::runtime_error naming PATH.
void write_file_atomically(const std::string& path, const std::string& text);
// The whole file; throws std::runtime_error naming PATH.
std::string read_whole_file(const std::string& path);

}  // namespace clothsim::analysis
