// What clothsim.bench, .stability and .converge share: a study run with the GIL released and
// stopped by Ctrl-C, its table as a DataFrame, the scene as the CLI's scene options, and a
// --shard part's rows read back. The studies' plans, runs and files are src/clip/studies' (the
// CLI's own code); these only turn keywords into its option structs and results into DataFrames.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <future>
#include <optional>
#include <string>

#include "scene_binding.h"
#include "clip/common/scene_options.h"
#include "study/tables/csv_tables.h"

namespace clothsim::python {

// Runs `work(stop)` on its own thread with the GIL released, checking Python's signals every
// 0.1 s from this (the main) thread: a KeyboardInterrupt stops the work through `stop`, waits for
// it, and is raised (before any file is written: the callers write after the work returns).
template <typename Work>
auto interruptible(Work work) {
  std::atomic<bool> stop{false};
  auto result = std::async(std::launch::async, [&] { return work([&stop] { return stop.load(); }); });
  for (;;) {
    {
      pybind11::gil_scoped_release release;
      if (result.wait_for(std::chrono::milliseconds(100)) == std::future_status::ready) break;
    }
    if (PyErr_CheckSignals() != 0) {
      stop = true;
      {
        pybind11::gil_scoped_release release;
        result.wait();
      }
      throw pybind11::error_already_set();
    }
  }
  return result.get();
}

// A study's table as a DataFrame: its CSV text as pandas.read_csv reads the CLI's --csv file
// (float_precision="round_trip": every number to the last bit; an empty cell is NaN), so a
// DataFrame is the CLI's CSV read back, whichever keywords made it.
pybind11::object data_frame(const analysis::CsvTable& table);
// The same for CSV text the library writes as text (bench --scale's, a shard's joined rows).
pybind11::object csv_frame(const std::string& text);

// The rows a --shard part holds (this run's and an earlier run's of the same part), in item
// order, as a DataFrame with the study's columns.
pybind11::object shard_frame(const std::string& csv, const std::string& shard);

// The scene's file and --set strings as the CLI's options (its step as --set dt: a study
// reloads the scene for each swept value), and its duration= as --duration where `duration`
// is not given; max_memory= as --max-memory.
clip::SceneOptions scene_options(const Scene& scene, const std::optional<double>& duration,
                                 const pybind11::object& max_memory);

// frame_dts=: None (the CLI's default), [] or "none" (none), numbers or fractions.
std::string frame_dts_text(const pybind11::object& frame_dts, const std::string& fallback);

void bind_bench(pybind11::module_& m);

}  // namespace clothsim::python
