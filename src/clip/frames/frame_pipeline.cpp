#include "frame_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>

#include "frame_decoration.h"
#include "overlay_text.h"
#include "plausibility.h"
#include "reference_lanes.h"
#include "core/model/stiffness_estimate.h"
#include "core/run/work_units.h"
#include "clip/common/cli_common.h"
#include "clip/common/progress.h"

namespace clothsim::clip {

namespace {

using Clock = std::chrono::steady_clock;

class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), start_(Clock::now()) {}
  ~Stopwatch() { total_ += std::chrono::duration<double>(Clock::now() - start_).count(); }
 private:
  double& total_;
  Clock::time_point start_;
};

// One target's worth of lane frames, held until its colour scale is known.
struct TargetFrames {
  Target target;
  std::vector<std::shared_ptr<const LaneFrame>> frames;  // per lane; a frozen lane's repeats
  std::vector<bool> fresh;
  std::vector<std::vector<float>> fields;  // per lane, fresh lanes only: the colouring field
  std::vector<double> largest;             // per lane: the field's largest value (NaN: none)
  std::vector<std::string> wrong;          // per lane: the plausibility verdict so far ("" none)
};

}  // namespace

std::optional<OverlayMode> parse_overlay_mode(std::string_view text) {
  if (text == "full") return OverlayMode::Full;
  if (text == "label") return OverlayMode::Label;
  if (text == "none") return OverlayMode::None;
  return std::nullopt;
}

std::vector<std::string> lane_overlay(const Model& model, const Lane& lane, const LaneFrame& frame,
                                      OverlayMode mode, bool single, bool cpu) {
  std::vector<std::string> lines;
  if (mode == OverlayMode::None) return lines;
  if (mode == OverlayMode::Label) {
    if (single) lines.push_back(lane.label());  // a tile's label is the grid's
    return lines;
  }
  // run: the scene, the lane and the time (overlay_text.h); a tile: the time, the grid labels it.
  lines = single ? overlay_lines(model, lane.label(), frame.t) : std::vector<std::string>{overlay_time_line(frame.t)};
  lines.push_back(cost_line(spring_passes(frame.totals), frame.totals.cpu_seconds, frame.t, cpu));
  return lines;
}

std::optional<ColorRange> range_from_data(const std::vector<const std::vector<float>*>& fields, FieldKind kind) {
  double top = 0.0;
  for (const std::vector<float>* f : fields)
    for (float v : *f)
      if (std::isfinite(v) && v > top) top = v;
  if (!(top > 0.0)) return std::nullopt;
  const double hi = std::pow(10.0, std::ceil(std::log10(top) - 1e-9));
  // Four decades for the error: methods differ by orders of magnitude and all should show.
  const double decades = kind == FieldKind::Error ? 4.0 : 3.0;
  return ColorRange{hi / std::pow(10.0, decades), hi};
}

struct FramePipeline::Impl {
  const Model& model;
  const TargetPlan& plan;
  PipelineConfig config;
  Renderer* renderer;
  std::vector<Lane> lanes;
  std::vector<MethodSettings> settings;  // per lane, what its run steps with (lane_settings)
  std::vector<std::unique_ptr<LaneWorker>> workers;
  ReferenceLanes references;  // the error colouring's and the energy inset's (never shown)
  std::vector<std::unique_ptr<FrameOutput>> outputs;
  std::vector<double> output_seconds;

  std::vector<std::shared_ptr<const LaneFrame>> current;
  std::vector<bool> frozen;
  std::vector<Image> images;
  std::vector<EnergyHistory> energy;  // per lane, for the inset
  // Per lane, a frame handed over but not yet rendered, with its field.
  std::vector<std::pair<std::shared_ptr<const LaneFrame>, std::vector<float>>> unrendered;
  // Per lane, its latest frame before it diverged, with its field: a diverged tile's colouring.
  std::vector<std::pair<std::shared_ptr<const LaneFrame>, std::vector<float>>> last_sane;
  std::vector<double> predicted_limits;  // per lane, s: predicted_limit_of's, once asked
  bool bodies = false;                         // an output needs_bodies()
  std::vector<std::vector<float>> last_field;  // per lane, with bodies: its latest field (LaneView::field)
  std::deque<TargetFrames> held;      // targets waiting for the colour scale
  std::vector<LaneReport> reports;       // per lane: its field, verdict and energy so far (result at the end)
  std::vector<std::int64_t> field_step;  // per lane: the step of the last state measured
  std::vector<double> energy0;           // per lane: E(0), J
  std::optional<ColorRange> range;
  std::optional<ColorScale> legend;  // the scale of range, as the outputs draw it
  double wait_seconds = 0.0, render_seconds = 0.0;
  long processed = 0;

  Impl(const Model& m, const TargetPlan& p, std::vector<Lane> l, PipelineConfig c, Renderer* r)
      : model(m), plan(p), config(std::move(c)), renderer(r), lanes(std::move(l)), range(config.color_range) {}

  LaneNeeds needs() const {
    LaneNeeds n;
    n.picture = config.rendering;
    n.look = config.scene_render;
    n.metrics = config.metrics || config.judge;  // judging reads the energies
    // The inset's curve: sampled at the clip's frame rate whatever the targets (a still too).
    if (config.inset_energy) n.energy_every = 1.0 / plan.fps();
    n.positions = config.color == FieldKind::Error;
    if (config.color == FieldKind::Strain || config.color == FieldKind::Speed) n.field = config.color;
    n.final_state = config.final_state;
    n.bodies = bodies;
    n.hold_sane = config.tiles;  // a diverged tile shows its last sane state (frame_pipeline.h)
    return n;
  }

  void start() {
    const auto interrupt = [] { return interrupted(); };
    for (std::size_t i = 0; i < lanes.size(); ++i) settings.push_back(lane_settings(model_of(i), lanes[i]));
    for (std::size_t i = 0; i < lanes.size(); ++i)
      workers.push_back(std::make_unique<LaneWorker>(model_of(i), settings[i], lanes[i], plan, needs(),
                                                     kLaneQueueCapacity, interrupt));
    std::vector<const Model*> models;
    for (std::size_t i = 0; i < lanes.size(); ++i) models.push_back(&model_of(i));
    references.start(model, plan, lanes, models, config, interrupt);
    current.resize(lanes.size());
    frozen.assign(lanes.size(), false);
    images.resize(lanes.size());
    energy.resize(lanes.size());
    unrendered.resize(lanes.size());
    last_sane.resize(lanes.size());
    reports.assign(lanes.size(), LaneReport{});
    field_step.assign(lanes.size(), -1);
    energy0.assign(lanes.size(), std::numeric_limits<double>::quiet_NaN());
    output_seconds.assign(outputs.size(), 0.0);
  }

  const Model& model_of(std::size_t lane) const {
    return config.lane_models.empty() ? model : *config.lane_models[lane];
  }

  // The step the stiffness estimate predicts stable for lane `i`'s method on the model it runs,
  // under its settings (the fixed point's limit is not backward Euler's): what its caption
  // says if it diverges.
  double predicted_limit_of(std::size_t i) {
    if (predicted_limits.empty())
      for (std::size_t k = 0; k < lanes.size(); ++k)
        predicted_limits.push_back(analysis::predicted_limit(analysis::estimate_stiffness(model_of(k)), lanes[k].kind,
                                                             settings[k].implicit));
    return predicted_limits[i];
  }

  // Lane `i`'s picture of `f` (the frame handed over last) with its colouring `field`. A tile
  // that diverged shows its last sane state (LaneNeeds::hold_sane), coloured as it was at that
  // target and with its time ("t = 0.033 s, last sane frame"), under the DIVERGED banner and
  // the step predicted stable; `run` shows the blow-up.
  RenderFrame picture_of(std::size_t i, const LaneFrame& f, const std::vector<float>*& field) {
    const bool holding = f.divergence && config.tiles;
    // (the error is measured in this thread: the sane state's, where it was a target)
    if (holding && field->empty() && last_sane[i].first && last_sane[i].first->step == f.step) field = &last_sane[i].second;
    RenderFrame rf = f.frame;
    rf.overlay_lines = lane_overlay(model_of(i), lanes[i], f, config.overlay, !config.tiles, config.overlay_cpu);
    if (holding && config.overlay == OverlayMode::Full && !rf.overlay_lines.empty())
      rf.overlay_lines.front() = overlay_time_line(f.shown_t) + ", last sane frame";  // the cost: to the blow-up
    if (f.divergence && config.overlay != OverlayMode::None) mark_diverged(rf, *f.divergence, predicted_limit_of(i));
    return rf;
  }

  // The plausibility evidence a fresh frame adds (energy), and the verdict once a rule breaks.
  void judge(std::size_t i) {
    const LaneFrame& f = *current[i];
    if (f.divergence) return;  // DIVERGED says more
    const double e = f.metrics.energies.total();
    if (std::isnan(energy0[i])) energy0[i] = e;
    LaneReport& r = reports[i];
    if (std::isfinite(e)) r.energy_rise = std::max(r.energy_rise, e - energy0[i]);
    if (!r.wrong.empty()) return;
    LaneEvidence evidence{f.totals, config.color == FieldKind::Error && r.field_count > 0 ? r.field_max : -1.0};
    if (const auto verdict = implausible(model_of(i), evidence)) r.wrong = *verdict;
  }

  void stop_lanes() {
    for (auto& w : workers) w->stop();
    references.stop();
  }

  // The lanes' frames at `target`; false on a signal.
  bool collect(const Target& target, TargetFrames& out) {
    out.target = target;
    out.fresh.assign(lanes.size(), false);
    out.fields.assign(lanes.size(), {});
    out.largest.assign(lanes.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      if (!frozen[i]) {  // a diverged lane holds its last picture
        LaneFrame f;
        Stopwatch watch(wait_seconds);
        const bool got = workers[i]->next(f);
        if (interrupted()) return false;  // next() gives up on a signal
        if (got) {
          frozen[i] = f.frozen;
          // A lane that diverged has no error from here on: the reference stops serving it
          // (and running, once no live lane needs it further) before it is asked for this target.
          if (f.frozen) references.drop_lane(i);
          current[i] = std::make_shared<const LaneFrame>(std::move(f));
          out.fresh[i] = true;
        }
      }
    }
    if (!references.collect(wait_seconds)) return false;
    out.frames = current;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      if (!out.fresh[i] || !current[i]) continue;
      if (config.color == FieldKind::Error) {
        // (a reference that diverged hands over the targets it had served in part: null where not)
        const LaneFrame* r = references.frame_for(i);
        if (references.fresh_for(i) && !current[i]->x.empty() && r->x_for[i])
          out.fields[i] = vertex_distance(current[i]->x, *r->x_for[i]);
      } else {
        out.fields[i] = current[i]->field;
      }
      if (out.fields[i].empty()) continue;
      double largest = 0.0;
      for (float v : out.fields[i]) largest = std::max(largest, static_cast<double>(v));
      out.largest[i] = largest;
      LaneReport& r = reports[i];
      r.field_last = largest;
      r.field_last_t = current[i]->t;
      if (r.field_count++ == 0) r.field_first_t = current[i]->t;
      if (current[i]->step != field_step[i]) {  // a lane that did not step shows the same state
        ++r.field_states;
        field_step[i] = current[i]->step;
      }
      if (!(r.field_max >= largest)) r.field_max = largest;
    }
    if (config.judge)
      for (std::size_t i = 0; i < lanes.size(); ++i)
        if (out.fresh[i] && current[i]) judge(i);
    out.wrong.clear();
    for (const LaneReport& r : reports) out.wrong.push_back(r.wrong);
    return true;
  }

  bool all_frozen() const { return std::all_of(frozen.begin(), frozen.end(), [](bool f) { return f; }); }

  void fix_range() {
    if (range || config.color == FieldKind::None) return;
    // Lanes that diverged within the window are left out (unless every lane did): the states
    // before a blow-up is caught are already far off (strain in the hundreds, speeds of km/s),
    // and a scale fitted to them would leave every lane that ran on one flat colour. Their
    // held pictures then show at the top of the scale.
    const bool all_diverged = all_frozen();
    std::vector<const std::vector<float>*> data;
    bool left_out = false;
    for (const TargetFrames& t : held)
      for (std::size_t i = 0; i < t.fields.size(); ++i) {
        if (frozen[i] && !all_diverged) {
          left_out = left_out || !t.fields[i].empty();
          continue;
        }
        data.push_back(&t.fields[i]);
      }
    range = range_from_data(data, config.color);
    const bool from_data = range.has_value();
    if (!range) range = ColorRange{1e-6, 1e-3};  // nothing to scale by
    if (!quiet())
      std::fprintf(stderr, "%s: colour scale for %s: %g to %g%s, %s (set it with --color-range LO,HI)\n",
                   config.command.c_str(), std::string(field_kind_name(config.color)).c_str(), range->lo, range->hi,
                   field_unit(config.color).c_str(),
                   !from_data  ? nothing_to_scale_by(all_diverged).c_str()
                   : left_out ? "from the first second of the lanes that did not diverge"
                              : "from the first second");
  }

  // Why the first second had no value above 0: every lane (or the reference the error is
  // measured against) diverged before one was measured, its states up to then matching (the
  // start, where every lane is the scene's initial state); else the cloth is at rest.
  std::string nothing_to_scale_by(bool all_diverged) const {
    const std::string field(field_kind_name(config.color));
    char text[192];
    if (all_diverged) {
      double last = 0.0;
      for (const auto& f : current)
        if (f && f->divergence) last = std::max(last, f->divergence->t);
      if (lanes.size() == 1)
        std::snprintf(text, sizeof text, "a default: the %s diverged at t = %.6g s before any %s above 0 was measured",
                      config.command == "run" ? "run" : "lane", last, field.c_str());
      else
        std::snprintf(text, sizeof text,
                      "a default: every lane diverged (the last at t = %.6g s) before any %s above 0 was measured", last,
                      field.c_str());
      return text;
    }
    if (const LaneFrame* r = references.diverged(); r && config.color == FieldKind::Error) {
      std::snprintf(text, sizeof text, "a default: the reference diverged at t = %.6g s before any error above 0 was measured",
                    r->divergence->t);
      return text;
    }
    return "the first second is at rest";
  }

  void process(const TargetFrames& t) {
    if (config.inset_energy)
      for (std::size_t i = 0; i < lanes.size(); ++i)
        if (t.fresh[i] && t.frames[i])
          for (const auto& [time, e] : t.frames[i]->energy) energy[i].add(time, e);
    // A target no output takes a picture at (one the colour scale looks at) renders nothing;
    // a lane's new frame is rendered at the first target that shows it.
    const bool shown = t.target.frame >= 0 || t.target.column >= 0 || t.target.still;
    std::vector<LaneView> views(lanes.size());
    if (config.color != FieldKind::None && range && !legend) legend = field_scale(config.color, *range);
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      views[i] = LaneView{&lanes[i], t.frames[i].get(), config.rendering ? &images[i] : nullptr, t.fresh[i],
                          legend ? &*legend : nullptr};
      if (t.frames[i] && t.frames[i]->divergence) views[i].predicted_limit = predicted_limit_of(i);
      if (t.fresh[i]) views[i].field_largest = t.largest[i];
      if (t.fresh[i]) unrendered[i] = {t.frames[i], t.fields[i]};
      if (t.fresh[i] && t.frames[i] && !t.frames[i]->divergence) last_sane[i] = {t.frames[i], t.fields[i]};
      if (bodies) {  // --export's error: a lane that stands on one state keeps its field
        last_field.resize(lanes.size());
        if (t.fresh[i]) last_field[i] = t.fields[i];
        views[i].field = &last_field[i];
      }
      if (!config.rendering || !shown || !unrendered[i].first) continue;
      const LaneFrame& f = *unrendered[i].first;
      const std::vector<float>* shown_field = &unrendered[i].second;
      RenderFrame rf = picture_of(i, f, shown_field);
      const std::vector<float>& field = *shown_field;
      rf.width = config.width;
      rf.height = config.height;
      if (config.camera) rf.camera = *config.camera;
      rf.samples = config.samples;
      rf.fxaa = config.fxaa;
      // A diverged tile's banner is picture_of's: DIVERGED says more than the rest.
      if (config.overlay != OverlayMode::None && !f.divergence) {
        if (f.totals.unconverged_steps > 0 && !lanes[i].newton_capped()) {
          // An implicit step that stalled above its tolerance is a result, shown on the picture.
          mark_not_converged(rf, f.totals.unconverged_steps);
        } else if (!t.wrong.empty() && !t.wrong[i].empty()) {
          mark_wrong(rf, t.wrong[i]);  // finite, but not this cloth's motion
        }
        // A lane that ran on but has no error field: the reference it is measured against
        // blew up. The tile says why it is drawn in the checker, not only stderr.
        const LaneFrame* reference_frame = references.frame_for(i);
        if (config.color == FieldKind::Error && field.empty() && reference_frame && reference_frame->divergence) {
          char line[96];
          std::snprintf(line, sizeof line, "no error colour (reference diverged at %.3g s)",
                        reference_frame->divergence->t);
          rf.overlay_lines.emplace_back(line);
        }
        // Every error drawn comes with the reference's own (study/reference.h), so far.
        if (config.color == FieldKind::Error && !field.empty() && reference_frame && reference_frame->reference_error > 0.0) {
          char line[96];
          const double e = reference_frame->reference_error;  // rounded up to two digits: "<=" holds
          const double unit = std::pow(10.0, std::floor(std::log10(e)) - 1.0);
          std::snprintf(line, sizeof line, "reference error <= %.2g m", std::ceil(e / unit) * unit);
          rf.overlay_lines.emplace_back(line);
          // The colours of an error the reference cannot tell are no result: the tile says so,
          // as the table does (compare showed them as a plain error map).
          if (reports[i].field_max < kUnresolvedFactor * e)
            rf.overlay_lines.emplace_back("UNRESOLVED");
        }
      }
      if (config.color != FieldKind::None && !field.empty())
        color_by_field(rf, field, config.color, *range, /*bar_outside=*/config.tiles);
      if (config.inset_energy)
        draw_energy_inset(rf, energy, i, plan.last_time(), references.energy(), frozen);
      Stopwatch watch(render_seconds);
      images[i] = renderer->render(rf);
      unrendered[i] = {};
    }
    for (std::size_t o = 0; o < outputs.size(); ++o) {
      Stopwatch watch(output_seconds[o]);
      outputs[o]->on_target(t.target, views);
    }
    ++processed;
  }

  // The phases of run(): every target through the lanes and the outputs, the outputs
  // finished, and on a signal or a failure what stays said in one line.
  std::unique_ptr<Progress> progress;
  std::vector<std::string> not_written;  // outputs the caller writes after the pipeline
  bool stopped = false;                  // a signal: stop_here's message already says what stays
  std::size_t finished = 0;              // outputs finished
  double reached_t = 0.0;                // s: the last target every lane reached

  RuntimeFailure stop_here(double t) {
    stopped = true;
    stop_lanes();
    progress.reset();
    std::vector<std::string> kept, lost;
    for (std::size_t o = 0; o < outputs.size(); ++o) {
      if (o < finished) outputs[o]->kept(kept);
      else outputs[o]->abandon(kept, lost);
    }
    lost.insert(lost.end(), not_written.begin(), not_written.end());
    return RuntimeFailure(interruption_message(t, kept, lost));
  }

  // A failure (a full disk, ulimit -f) is handled as a signal is: the outputs not finished are
  // dropped, and the one-line error says what stays (the PNGs already written, the outputs
  // finished before the one that failed) and what is not written.
  RuntimeFailure failure(const std::runtime_error& e) {
    stop_lanes();
    progress.reset();
    std::vector<std::string> kept, lost;
    for (std::size_t o = 0; o < outputs.size(); ++o) {
      if (o < finished) outputs[o]->kept(kept);
      else outputs[o]->abandon(kept, lost);
    }
    lost.insert(lost.end(), not_written.begin(), not_written.end());
    const bool render = dynamic_cast<const RenderError*>(&e) != nullptr;  // (said as main says it)
    return RuntimeFailure(std::string(render ? "render: " : "") + e.what() + "; " + what_stays(kept, lost));
  }

  void walk_targets() {
    // Targets wait for the colour scale while it is chosen from the data (the first second).
    const bool choosing_range = config.color != FieldKind::None && !range;
    const double window_end = std::min(kColorScaleWindow, plan.duration());
    TargetPlan::Cursor cursor(plan);
    long n = 0;
    double& last_t = reached_t;
    bool ended = false;  // stop_when_all_frozen, and every lane has diverged
    for (Target target; cursor.next(target); ++n) {
      if (interrupted()) throw stop_here(last_t);
      if (ended) {
        // A run that diverged ends its clip there; a still or sheet column still to come shows
        // the held picture of the blow-up.
        if (!target.still && target.column < 0) continue;
        target.frame = -1;
      }
      TargetFrames frames;
      if (!collect(target, frames)) throw stop_here(last_t);  // where the run stood, not where it was going
      last_t = target.t;
      if (choosing_range && !range) {
        held.push_back(std::move(frames));
        if (target.t >= window_end - 1e-9 || (config.stop_when_all_frozen && all_frozen())) flush_held();
      } else {
        process(frames);
      }
      progress->update(n + 1);
      ended = config.stop_when_all_frozen && all_frozen();
    }
    if (interrupted()) throw stop_here(last_t);
    flush_held();  // a clip shorter than the window, or one that stopped inside it
  }

  void finish_outputs() {
    progress.reset();
    for (; finished < outputs.size(); ++finished) {
      Stopwatch watch(output_seconds[finished]);
      outputs[finished]->finish();
    }
  }

  PipelineReport report() {
    PipelineReport r;
    r.lanes = reports;
    for (std::size_t i = 0; i < workers.size(); ++i) {
      workers[i]->join();
      r.lanes[i].result = workers[i]->result();
    }
    r.references = references.finish();
    for (std::size_t i = 0; i < r.lanes.size(); ++i) r.lanes[i].reference = references.reference_of(i);
    r.color_range = range;
    r.wait_seconds = wait_seconds;
    r.render_seconds = render_seconds;
    for (std::size_t o = 0; o < outputs.size(); ++o) r.output_seconds.emplace_back(outputs[o]->what(), output_seconds[o]);
    r.targets = processed;
    return r;
  }

  void flush_held() {
    fix_range();
    while (!held.empty()) {
      process(held.front());
      held.pop_front();
    }
  }
};

const LaneResult* lane_reference(const PipelineReport& report, std::size_t lane) {
  const int r = report.lanes[lane].reference;
  return r < 0 ? nullptr : &report.references[r].result;
}

FramePipeline::FramePipeline(const Model& model, const TargetPlan& plan, std::vector<Lane> lanes,
                             PipelineConfig config, Renderer* renderer)
    : impl_(std::make_unique<Impl>(model, plan, std::move(lanes), std::move(config), renderer)) {}

FramePipeline::~FramePipeline() = default;

void FramePipeline::add(std::unique_ptr<FrameOutput> output) {
  impl_->bodies = impl_->bodies || output->needs_bodies();
  impl_->outputs.push_back(std::move(output));
}

PipelineReport FramePipeline::run(const std::string& progress_label, const std::vector<std::string>& not_written) {
  Impl& p = *impl_;
  p.not_written = not_written;
  p.start();
  p.progress = std::make_unique<Progress>(progress_label, p.plan.size(), "frames");
  try {
    p.walk_targets();
    p.finish_outputs();
  } catch (const std::runtime_error& e) {  // RuntimeFailure, PngError, RenderError, OutputFileError
    if (p.stopped || dynamic_cast<const UsageError*>(&e)) throw;
    // A write the signal broke off (a FIFO output opened with no reader: EINTR) is the signal's
    // stop, said as one: "stopped by SIGTERM", not "Interrupted system call".
    if (interrupted()) throw p.stop_here(p.reached_t);
    throw p.failure(e);
  }
  return p.report();
}

}  // namespace clothsim::clip
