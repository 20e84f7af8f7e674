// What a reference lane handed over (its frames and its result), as the reference cache keeps it
// (study/reference_cache.h): the run that computes a reference records it, and the next run that
// asks for the same reference replays it instead of solving again, frame for frame, so its
// outputs are the same bytes.
//
// The key names everything the frames depend on: the model's content, the reference's method,
// step and tolerances, the lanes' landing grids (the times it stands at) and which it serves,
// the energy samples' interval, every target's time, and the build. Only a reference whose
// method reads nothing of the model but its physics is cached: the adaptive solve (study/
// reference.h) and the explicit fixed-step family without parameters (`--reference rk4@1e-5`);
// an implicit or iterative `--reference` reads settings the key leaves out, so it always runs.
//
// The record is held in memory until the reference has finished, then stored: at most
// kReferenceRecordLimit bytes (a longer one is dropped as it grows, and that run is not cached).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lane_worker.h"

namespace clothsim::clip {

// What a record may grow to in memory before it is given up (the cache's cap permitting).
inline constexpr double kReferenceRecordLimit = 256.0 * 1024 * 1024;

// The key of the reference `spec` (adaptive at `adaptive_tolerance` when > 0) standing in for
// lanes landing on `lane_steps` (serving those `serves` marks, all when empty), sampling its
// energy every `energy_every` s, over `targets`; nullopt when such a reference is not cached.
std::optional<std::string> reference_cache_key(const Model& model, const Lane& spec, double adaptive_tolerance,
                                               const std::vector<double>& lane_steps, const std::vector<bool>& serves,
                                               double energy_every, const TargetPlan& targets);

// Appends frames to a record as they are handed over; the result last.
class ReferenceRecorder {
 public:
  explicit ReferenceRecorder(std::size_t limit) : limit_(limit) {}
  void add(const LaneFrame& frame);
  bool overflowed() const { return overflowed_; }
  // The payload: every frame added, then `result`. Empty once overflowed.
  std::string finish(const LaneResult& result);

 private:
  std::size_t limit_;
  bool overflowed_ = false;
  long frames_ = 0;
  std::string body_;
};

struct ReferenceRecord {
  std::vector<LaneFrame> frames;
  LaneResult result;  // its spec not stored: the caller's
};
// nullopt when `payload` is not a whole record (the cache checked its checksum already: a
// record that still does not parse is treated as damaged).
std::optional<ReferenceRecord> decode_reference_record(const std::string& payload);

// Bytes a record of `particles` standing for lanes of `lane_steps` over `targets` targets can
// hold in memory (compare's memory estimate): a copy of the positions per distinct step a
// target, within kReferenceRecordLimit.
double reference_record_bytes(int particles, const std::vector<double>& lane_steps, long targets);

}  // namespace clothsim::clip
