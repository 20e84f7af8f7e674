// What `bench` and `stability` share: list options (--integrators, --dts, --values),
// CSV cells, progress across threads, and drawing a figure with a tools/ plot script.
#pragma once

#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "clip/common/cli_common.h"
#include "clip/common/summary_json.h"
#include "core/integrators/integrator_kind.h"
#include "study/study.h"
#include "io/csv_cells.h"

namespace clothsim::clip {

// "1e-4,2e-4,1/60" -> numbers (fractions allowed); an empty list, an empty item or a word is
// a UsageError naming `option`. Signs are the caller's to check (a dt must be > 0, a parameter may be anything).
std::vector<double> parse_number_list(const std::string& text, const std::string& option);

// The steps of one step per video frame that bench and stability also run implicit_euler at.
inline constexpr const char* kDefaultFrameDts = "1/240,1/120,1/60,1/30";

// --frame-dts: "none", or steps as numbers or fractions ("1/60"); a UsageError names the item.
std::vector<double> parse_frame_dts(const std::string& text);

// A CSV cell is io/csv_cells.h's csv_number and csv_text (the Python module's tables spell theirs the same way).

// bench's --summary keys beside its lanes: T, whether every run finished, and the reference
// (its integrator and step, or "dopri5 (adaptive)" and 0; how far halving its step or
// tightening its tolerance moved the particles, RMS, as change_rms and estimated_error_m; and
// whether it is converged). One writer for the single process and `clothsim merge`.
JsonObject bench_summary_keys(double duration, bool complete, const std::string& reference, double reference_dt,
                              double change_rms, bool converged);

// The line `bench` and `stability` end on when stopped before the study finished (main adds
// "clothsim: "): how many of its `total` runs or searches finished, and every file that stays
// on disk, each marked incomplete while some did not finish, and the plot that is not drawn:
// "interrupted: 3 of 28 runs finished; kept wp.csv (incomplete), wp.json (incomplete); not
// written: wp.png". `kept`: the CSV and summary written (empty paths skipped); `plot`: "" for none.
std::string study_interrupted_message(std::size_t finished, std::size_t total, const std::string& unit,
                                      const std::vector<std::string>& kept, const std::string& plot);

// Progress for work finished on worker threads: update() may be called from any thread.
class SharedProgress {
 public:
  SharedProgress(std::string label, long total, std::string unit);
  // The count done, and the time left from the study's share of its work (StudyProgress::share).
  void update(const analysis::StudyProgress& progress);
  // What a study's StudyHooks::progress is set to: update(), on this printer.
  std::function<void(const analysis::StudyProgress&)> hook();
  void finish();  // clears the line before results are printed
 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
};

// A figure drawn by tools/SCRIPT with python3 and matplotlib (Agg, no display needed).
// Checked before a study starts, so a missing python3-matplotlib fails in a second, not
// after minutes of simulation.
class PlotScript {
 public:
  // Throws RuntimeFailure when the script, python3 or matplotlib is missing, and checks
  // that `png` can be written.
  PlotScript(std::string script, std::string png);
  // Runs python3 SCRIPT ARGS... --out /dev/fd/3, a nameless file of ours named when the
  // script succeeds; the script is in its own process group, dies with us, and is killed on
  // a signal. Throws RuntimeFailure when the script fails (its stderr is passed through) or a
  // signal stops it.
  void draw(const std::vector<std::string>& args) const;
  // Draws from the study's CSV: `csv` when the user asked for one (already written there),
  // otherwise a nameless CSV written by `write_csv(path)` and read by the script as /dev/fd/4.
  // Passes "--csv PATH" before `args`, and says "plot: PNG" on stdout. `written`: the outputs
  // written before the plot (empty paths skipped), which a stop while drawing names as kept.
  void draw_from_csv(const std::string& csv, const std::function<void(const std::string&)>& write_csv,
                     const std::vector<std::string>& args, const std::vector<std::string>& written) const;
  const std::string& png() const { return png_; }
 private:
  // csv_fd: the child's /dev/fd/4
  void draw(const std::vector<std::string>& args, int csv_fd, const std::vector<std::string>& written) const;
  std::string python_, script_, png_;
};

// A study's outputs, checked before minutes of simulation: none is the scene or another output
// under any spelling, each one's folder is writable, and the plot's script, python3 and
// matplotlib are found (PlotScript). "" for an output not asked for; returns null without a plot.
std::unique_ptr<PlotScript> check_study_outputs(const std::string& scene, const std::string& csv,
                                                const std::string& summary, const std::string& plot,
                                                const std::string& plot_script);

// The directory holding the plot scripts (the source tree's tools/, or CLOTHSIM_TOOLS_DIR
// from the environment).
std::string tools_dir();

}  // namespace clothsim::clip
