// The outputs a frame pipeline feeds (frame_pipeline.h): each watches every target and
// takes what it needs. All of them write nothing under their name until complete.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "frame_pipeline.h"
#include "frame_sink.h"
#include "clip/frames/run_outputs.h"
#include "render/png_io.h"
#include "render/video/tiling.h"

namespace clothsim::clip {

// How lane pictures become one picture: a single lane's picture as it is (run), or the lanes
// composed into a grid, each tile labelled with its lane (compare; labels off with overlay none),
// with the grid's one colour bar in a strip at its right (grid_legend.h) when legend_width > 0.
struct Composer {
  std::optional<TileGrid> grid;     // none: the first lane's picture itself
  std::vector<std::string> labels;  // per lane
  int legend_width = 0;             // the colour bar's strip right of the grid (0: none)
  // The picture of `lanes` (composed into `canvas` when there is a grid).
  const Image& picture(const std::vector<LaneView>& lanes, Image& canvas) const;
  mutable Image body = {};  // scratch: the grid before the strip is added
};

// Each lane's tile label in `grid`: "rk4  dt = 1e-4 s", or, where one of them does not fit its
// tile at the grid's text size, every lane as --integrators spells it ("rk4@1e-4"), shorter
// and the same form in every tile; the grid shortens with "..." what still does not fit, the
// name and not the step ("sympl...@1e-4"), never two lanes alike (TileGrid::shown_labels).
std::vector<std::string> lane_tile_labels(const std::vector<Lane>& lanes, const TileGrid& grid);

// Clip frames of every lane's picture, composed, into a FrameSink (the MP4).
std::unique_ptr<FrameOutput> make_video_output(std::unique_ptr<FrameSink> sink, std::string path, Composer composer);

// Clip frames of one lane's picture into a PNG sequence (--frames): in compare, its tile as the
// grid shows it (the grid's one colour bar is not in it; the scale is on stderr and in --summary).
std::unique_ptr<FrameOutput> make_frames_output(std::unique_ptr<FrameSink> sink, std::size_t lane);

// The composed picture at the still's target, written to `path`.
std::unique_ptr<FrameOutput> make_still_output(std::string path, Composer composer, PngText meta);

// One row per lane, one column per sheet time, width x height (compose_contact_sheet); written at
// finish(). With `legend` the colour bar is drawn once, in a strip at the sheet's right taken out
// of the width, at the text size of the sheet's labels. A lane that diverged shows its held
// picture in the first column past the divergence, and the rest of its row is one wide cell
// with its caption (overlay_text.h, diverged_caption).
std::unique_ptr<FrameOutput> make_sheet_output(std::string path, std::vector<std::string> row_labels,
                                               std::vector<std::string> column_labels, PngText meta, int width,
                                               int height, bool legend = false);

// One CSV row per clip frame of one lane (run --metrics), the diverged state's row included.
std::unique_ptr<FrameOutput> make_metrics_output(std::unique_ptr<MetricsWriter> writer, std::string path, std::size_t lane);

// One lane at one clip frame, kept in memory for a front end that takes the values themselves
// (Python's compare: its attrs["frames"]): the FrameMetrics a --metrics row is written from and
// the colouring field's largest value (LaneView::field_largest).
struct LaneFrameRow {
  std::size_t lane = 0;  // in the pipeline's lane order
  double frame_t = 0.0;  // s: the frame's time, k / fps, or the end's (metrics.t: the state's)
  FrameMetrics metrics;
  double field = std::numeric_limits<double>::quiet_NaN();
};

// A row per lane per clip frame, and at `end` (the run's end, s) where that falls between
// frames, into `rows` (which must outlive the pipeline), in time order and lane order within
// one: every frame a lane hands over, a held state's again (its step tells), up to a diverged
// lane's last state, as --metrics writes it, and none after.
std::unique_ptr<FrameOutput> make_frame_rows_output(std::vector<LaneFrameRow>& rows, double end);

}  // namespace clothsim::clip
