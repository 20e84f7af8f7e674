// What `clothsim compare` will do, worked out and checked before any simulation: which
// integrators at which step sizes, at which times frames and contact-sheet columns fall.
// Every function throws UsageError with a one-line message naming the option.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "clip/common/lanes.h"
#include "core/integrators/integrator_kind.h"
#include "scene/param_keys.h"
#include "scene/scene_def.h"

namespace clothsim::clip {

// --dt: "" (every run at the scene's dt), "S" (every run at S), "name=S,name=S" (those runs
// at their own step, the others at the scene's), or a bare S mixed with name=S (the bare
// one for all not named). Names must be among `kinds`. Returns one dt per kind.
std::vector<double> parse_dt_list(const std::string& text, const std::vector<IntegratorKind>& kinds,
                                  double scene_dt);
// The same, nullopt for a kind --dt gives no step (it runs at the scene's).
std::vector<std::optional<double>> parse_dt_options(const std::string& text, const std::vector<IntegratorKind>& kinds);

// --times "0.5,1,2,4": strictly increasing, each in [0, duration].
std::vector<double> parse_times(const std::string& text, double duration);

// One instant the runs stop at: an output frame of the clip, a contact-sheet column, the
// still, or several of these. Targets are sorted by time and every run stops at all of them.
struct Target {
  double t = 0.0;
  int frame = -1;      // index of the clip frame at t, or -1
  int column = -1;     // contact-sheet column at t, or -1
  bool still = false;  // the --still picture is taken here
};

// The targets of a compare, in time order, generated as they are needed rather than stored:
// a clip of duration 5e7 s has more frames than memory holds (validation bounds the count,
// run_bounds.h, but a million Target structs per lane would still be waste).
// Frames at t = k / fps for k = 0 .. floor(duration * fps) (t = 0 and, when it falls on a
// frame, t = duration included, as `run` does) when `with_frames`; sheet times and the
// still's time (if >= 0) merged in, a time within a microsecond of a frame being that frame.
// With no frames, sheet or still, one target at `duration` (a summary-only compare); with
// `to_end`, a target at `duration` whatever else there is (a run's final state is at its end
// even when that is not a whole frame).
class TargetPlan {
 public:
  TargetPlan(double duration, double fps, bool with_frames, const std::vector<double>& sheet_times,
             double still_t = -1.0, bool to_end = false);
  // With `scale_window` > 0, the clip's frame times up to it are targets even when no frame
  // is written (frame -1: nothing takes a picture there): a colour scale chosen from the first
  // second's data sees the same instants whether the output is a clip, a sheet or a still.
  TargetPlan& with_scale_window(double scale_window);
  long size() const { return size_; }      // targets in all
  double duration() const { return duration_; }
  double fps() const { return fps_; }
  long frames() const { return frames_; }  // clip frames among them
  double last_time() const;                // s: the last target's time (the clip's end, or the last still or column)

  // Walks the plan's targets in order; each walker (a run's thread, the renderer) has its own.
  class Cursor {
   public:
    explicit Cursor(const TargetPlan& plan) : plan_(&plan) {}
    bool next(Target& out);  // false after the last target
   private:
    const TargetPlan* plan_;
    long frame_ = 0;            // next clip frame
    std::size_t extra_ = 0;     // next sheet column / still
  };

 private:
  double frame_time(long k) const;
  // The extra target at time t, inserted in order unless one is already within a microsecond.
  Target& extra_at(double t);
  long frame_at(double t) const;  // the clip frame within a microsecond of t, or -1

  double duration_, fps_;
  long frames_ = 0, size_ = 0;
  std::vector<Target> extras_;  // sheet columns and the still (a few), sorted, merged with each other
};

// "t = 0.5 s" for a contact-sheet column.
std::string time_label(double t);

// A contact sheet's rows: each lane's label, or `labels` (--vary's) where given.
std::vector<std::string> sheet_rows(const std::vector<Lane>& lanes, const std::vector<std::string>& labels);
// A sheet of `rows` x `columns` cells of cell_w x cell_h, in width x height pixels: a UsageError
// naming --sheet when its labels and cells cannot fit, before the clip is simulated.
void check_sheet_fits(int cell_w, int cell_h, const std::vector<std::string>& rows, int columns, int width,
                      int height);

// --vary KEY=V1,V2,... (compare's lanes by value, bench's too): the key resolved against the
// scene (scene/param_keys.h) and the values, numbers or fractions, or words for a key that
// takes one (collision.model=projection,barrier: the scene's parser judges them). UsageError
// naming --vary, also for a value given twice (ks=100,1e2) and for the keys a lane owns, dt
// and integrator (the message gives the --integrators NAME@STEP lanes that say it).
struct Variation {
  ParamKey key;
  std::vector<double> values;       // numbers, or
  std::vector<std::string> words;   // words (one of the two is empty)
  int digits = 3;                   // figures in the labels: enough to tell every value apart
  std::size_t size() const { return values.empty() ? words.size() : values.size(); }
  std::vector<std::string> sets(std::size_t i) const;  // what --set would say for value i
  std::string label(std::size_t i) const;              // "ks = 2e4", "collision.model = barrier": unique
};
Variation parse_vary(const std::string& text, const SceneDef& scene);

// Every lane's step, and the error reference's, bounded like the scene's (scene/run_bounds.h):
// UsageError naming --dt or --reference.
void check_step_bounds(const SceneDef& scene, const std::vector<Lane>& lanes,
                       const std::optional<Lane>& reference);

}  // namespace clothsim::clip
