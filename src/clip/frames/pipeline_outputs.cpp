#include "pipeline_outputs.h"

#include <algorithm>

#include "grid_legend.h"
#include "overlay_text.h"
#include "render/color_bar.h"
#include "render/video/contact_sheet.h"

namespace clothsim::clip {

namespace {

// The grid's colour scale at this target (the pipeline's one scale; null before it is known).
const ColorScale* legend_of(const std::vector<LaneView>& lanes) {
  for (const LaneView& l : lanes)
    if (l.legend) return l.legend;
  return nullptr;
}

}  // namespace

const Image& Composer::picture(const std::vector<LaneView>& lanes, Image& canvas) const {
  if (!grid) return *lanes.front().image;
  std::vector<const Image*> tiles;
  for (const LaneView& l : lanes) tiles.push_back(l.image);
  if (legend_width <= 0) {
    grid->compose(tiles, labels, canvas);
    return canvas;
  }
  grid->compose(tiles, labels, body);
  add_legend_strip(body, legend_of(lanes), legend_width, grid->label_scale(), canvas);
  return canvas;
}

std::vector<std::string> lane_tile_labels(const std::vector<Lane>& lanes, const TileGrid& grid) {
  std::vector<std::string> labels;
  bool fit = true;
  for (const Lane& l : lanes) {
    labels.push_back(l.label());
    fit = fit && label_fits(labels.back(), grid.cell_width(), grid.label_scale());
  }
  if (!fit)
    for (std::size_t i = 0; i < lanes.size(); ++i) labels[i] = lanes[i].spelling();
  return labels;
}

namespace {

class VideoOutput final : public FrameOutput {
 public:
  VideoOutput(std::unique_ptr<FrameSink> sink, std::string path, Composer composer)
      : sink_(std::move(sink)), path_(std::move(path)), composer_(std::move(composer)) {}
  std::string what() const override { return "video"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.frame < 0) return;
    sink_->add(target.frame, target.t, composer_.picture(lanes, canvas_));
  }
  void finish() override { sink_->finish(); }
  void abandon(std::vector<std::string>&, std::vector<std::string>& lost) override {
    sink_->abandon();
    lost.push_back(path_);
  }
  void kept(std::vector<std::string>& kept) override {
    const std::string mp4 = sink_->written();  // (finished: its path)
    if (!mp4.empty()) kept.push_back(mp4);
  }
 private:
  std::unique_ptr<FrameSink> sink_;
  std::string path_;
  Composer composer_;
  Image canvas_;
};

class FramesOutput final : public FrameOutput {
 public:
  FramesOutput(std::unique_ptr<FrameSink> sink, std::size_t lane) : sink_(std::move(sink)), lane_(lane) {}
  std::string what() const override { return "frames"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    // The picture's own time: a diverged lane's is the divergence's, not the frame's.
    if (target.frame >= 0) sink_->add(target.frame, lanes[lane_].frame->t, *lanes[lane_].image);
  }
  void finish() override { sink_->finish(); }
  void abandon(std::vector<std::string>& kept, std::vector<std::string>&) override {
    sink_->abandon();
    this->kept(kept);  // PNGs already written are complete: they stay
  }
  void kept(std::vector<std::string>& kept) override {
    const std::string pngs = sink_->written();
    if (!pngs.empty()) kept.push_back(pngs);
  }
 private:
  std::unique_ptr<FrameSink> sink_;
  std::size_t lane_;
};

class StillOutput final : public FrameOutput {
 public:
  StillOutput(std::string path, Composer composer, PngText meta)
      : path_(std::move(path)), composer_(std::move(composer)), meta_(std::move(meta)) {}
  std::string what() const override { return "still"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (!target.still) return;
    PngText meta = meta_;
    meta.emplace_back("t", std::to_string(target.t));
    write_png(path_, composer_.picture(lanes, canvas_), meta);
    written_ = true;
  }
  void finish() override {}
  void abandon(std::vector<std::string>& kept, std::vector<std::string>& lost) override {
    (written_ ? kept : lost).push_back(path_);
  }
  void kept(std::vector<std::string>& kept) override {
    if (written_) kept.push_back(path_);
  }
 private:
  std::string path_;
  Composer composer_;
  PngText meta_;
  Image canvas_;
  bool written_ = false;
};

class SheetOutput final : public FrameOutput {
 public:
  SheetOutput(std::string path, std::vector<std::string> rows, std::vector<std::string> columns, PngText meta,
              int width, int height, bool legend)
      : path_(std::move(path)), rows_(std::move(rows)), columns_(std::move(columns)), meta_(std::move(meta)),
        cells_(rows_.size(), std::vector<Image>(columns_.size())), width_(width), height_(height), legend_(legend),
        held_(rows_.size(), -1), captions_(rows_.size()) {}
  std::string what() const override { return "sheet"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.column < 0) return;
    for (std::size_t i = 0; i < lanes.size() && i < cells_.size(); ++i) {
      cells_[i][static_cast<std::size_t>(target.column)] = *lanes[i].image;
      // The first column past a lane's divergence shows its held picture; the rest of the row
      // becomes one cell that says why (SheetSpan), not the same picture again.
      const LaneFrame* f = lanes[i].frame;
      if (f && f->divergence && (held_[i] < 0 || target.column < held_[i])) {
        held_[i] = target.column;
        captions_[i] = diverged_caption(*f->divergence, lanes[i].predicted_limit);
      }
    }
    if (const ColorScale* scale = legend_of(lanes)) scale_ = *scale;
  }
  void finish() override { write_png(path_, legend_ && scale_ ? sheet_with_legend() : sheet(width_), meta_); }
  void abandon(std::vector<std::string>&, std::vector<std::string>& lost) override { lost.push_back(path_); }
  void kept(std::vector<std::string>& kept) override { kept.push_back(path_); }
 private:
  std::string path_;
  std::vector<std::string> rows_, columns_;
  PngText meta_;
  std::vector<std::vector<Image>> cells_;
  int width_, height_;  // the sheet's size (0: the cells' own)
  bool legend_;
  std::optional<ColorScale> scale_;  // the cells' colour scale, once known
  std::vector<int> held_;            // per row: the first column showing its divergence (-1: none)
  std::vector<std::vector<std::string>> captions_;  // per row: what its divergence says (diverged_caption)

  std::vector<SheetSpan> spans() const {
    std::vector<SheetSpan> out;
    for (std::size_t r = 0; r < held_.size(); ++r)
      if (held_[r] >= 0 && held_[r] + 1 < static_cast<int>(columns_.size()))
        out.push_back(SheetSpan{static_cast<int>(r), held_[r] + 1, captions_[r]});
    return out;
  }
  Image sheet(int width) const { return compose_contact_sheet(cells_, rows_, columns_, {}, width, height_, spans()); }
  // The strip at the text size of the sheet's labels: that of its cells once shrunk to the size
  // asked for (found without the strip; the strip, a few characters wide, changes it little).
  Image sheet_with_legend() const {
    int cell_w = 1, cell_h = 1;
    for (const auto& row : cells_)
      for (const Image& c : row) cell_w = std::max(cell_w, c.width), cell_h = std::max(cell_h, c.height);
    const double f = contact_sheet_shrink(cell_w, cell_h, rows_, static_cast<int>(columns_.size()), {}, width_, height_);
    const int scale = text_scale_for_height(std::max(1, static_cast<int>(cell_h * f)));
    const int strip = render::color_bar_strip_width(scale_->label, scale);
    const Image body = sheet(width_ > 0 ? width_ - strip : 0);
    Image out;
    add_legend_strip(body, &*scale_, strip, scale, out);
    return out;
  }
};

class MetricsOutput final : public FrameOutput {
 public:
  MetricsOutput(std::unique_ptr<MetricsWriter> writer, std::string path, std::size_t lane)
      : writer_(std::move(writer)), path_(std::move(path)), lane_(lane) {}
  std::string what() const override { return "metrics"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.frame < 0 || !lanes[lane_].fresh) return;
    // A step longer than the frame interval stands on one state for several frames: one row
    // for it, not a copy per frame.
    const FrameMetrics& m = lanes[lane_].frame->metrics;
    if (m.step == last_step_) return;
    last_step_ = m.step;
    writer_->row(m);
  }
  void finish() override { writer_->commit(); }
  void abandon(std::vector<std::string>&, std::vector<std::string>& lost) override { lost.push_back(path_); }
  void kept(std::vector<std::string>& kept) override { kept.push_back(path_); }
 private:
  std::unique_ptr<MetricsWriter> writer_;
  std::string path_;
  std::size_t lane_;
  std::int64_t last_step_ = -1;
};

class FrameRowsOutput final : public FrameOutput {
 public:
  FrameRowsOutput(std::vector<LaneFrameRow>& rows, double end) : rows_(rows), end_(end) {}
  std::string what() const override { return "frame rows"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.frame < 0 && target.t != end_) return;  // a still's or a column's instant
    for (std::size_t i = 0; i < lanes.size(); ++i)
      if (lanes[i].fresh && lanes[i].frame) rows_.push_back({i, target.t, lanes[i].frame->metrics, lanes[i].field_largest});
  }
  void finish() override {}
  void abandon(std::vector<std::string>&, std::vector<std::string>&) override {}  // no file
 private:
  std::vector<LaneFrameRow>& rows_;
  double end_;
};

}  // namespace

std::unique_ptr<FrameOutput> make_video_output(std::unique_ptr<FrameSink> sink, std::string path, Composer composer) {
  return std::make_unique<VideoOutput>(std::move(sink), std::move(path), std::move(composer));
}
std::unique_ptr<FrameOutput> make_frames_output(std::unique_ptr<FrameSink> sink, std::size_t lane) {
  return std::make_unique<FramesOutput>(std::move(sink), lane);
}
std::unique_ptr<FrameOutput> make_still_output(std::string path, Composer composer, PngText meta) {
  return std::make_unique<StillOutput>(std::move(path), std::move(composer), std::move(meta));
}
std::unique_ptr<FrameOutput> make_sheet_output(std::string path, std::vector<std::string> row_labels,
                                               std::vector<std::string> column_labels, PngText meta, int width,
                                               int height, bool legend) {
  return std::make_unique<SheetOutput>(std::move(path), std::move(row_labels), std::move(column_labels), std::move(meta),
                                       width, height, legend);
}
std::unique_ptr<FrameOutput> make_metrics_output(std::unique_ptr<MetricsWriter> writer, std::string path, std::size_t lane) {
  return std::make_unique<MetricsOutput>(std::move(writer), std::move(path), lane);
}

std::unique_ptr<FrameOutput> make_frame_rows_output(std::vector<LaneFrameRow>& rows, double end) {
  return std::make_unique<FrameRowsOutput>(rows, end);
}

}  // namespace clothsim::clip
