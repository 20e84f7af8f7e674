// clothsim compare SCENE [--integrators NAME[@STEP],... | course] [--layout auto] [--video FILE.mp4]
//                        [--frames DIR] [--export PATH] [--dt S | --dt name=S,...] [--duration S] [--set K=V]...
//                        [--sheet FILE.png --times 0.5,1,2,4] [--still T -o FILE.png]
//                        [--color error|strain|speed|checker] [--reference NAME@STEP] [--inset energy]
//                        [--width W --height H] [--crf Q] [--preset P]
//
// The scene is loaded once and built into one Model; one lane per integrator and step runs on
// its own thread through the frame pipeline (frame_pipeline.h), which colours, labels and
// renders each lane's picture into a tile and feeds the outputs: the tiled clip, each lane's
// PNGs, the contact sheet, the still. A lane that diverges shows its last finite state with
// a DIVERGED banner while the others go on: in compare, divergence is a result (exit 0),
// shown in the clip and in the summary table.
//
// By default the lanes are matched on cost (step_matching.h: each free lane at the step where
// its work per simulated second equals the cheapest lane's at the scene's step) and the tiles
// coloured by each particle's distance from a reference run alongside and never shown (the
// adaptive dopri5 on a smooth scene, else RK4 at a quarter of the smallest step or within its
// predicted stable step: fit_reference_to_model), on one logarithmic scale whose colour bar is
// drawn once, in a strip beside the grid (grid_legend.h); each tile shows its work, and a lane
// that is finite but implausible is marked WRONG (plausibility.h): what each method buys for
// the same cost, on screen.
//
// The command reads as its phases: plan (check everything, build the model, choose the
// steps), outputs (the pipeline and what it feeds), run, report; the first two are the clip
// library's (src/clip/compare/compare_job.h), this file parses the options and prints.
//
// Outputs are checked before any simulation (unknown integrator or layout, unwritable
// paths, bad --dt or --times: milliseconds, exit 2 or 1), created without a name and
// named when complete. SIGINT / SIGTERM stop every lane before its next step, drop the incomplete
// outputs and exit 130 / 143 saying what stays: the files of --frames and --export written so far.
//
// Frame k is the state at t = k / fps for k = 0 .. floor(duration * fps), as in `run`.
// The summary (stdout) has one row per lane (and the reference's); the time breakdown
// (stderr) says where the wall time went.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/cli_common.h"
#include "clip/common/gl_options.h"
#include "clip/common/progress.h"
#include "clip/common/scene_options.h"
#include "clip/common/summary_json.h"
#include "clip/compare/compare_job.h"
#include "clip/compare/compare_shard.h"
#include "clip/compare/compare_summary.h"
#include "clip/frames/export_output.h"
#include "clip/frames/frame_pipeline.h"
#include "clip/frames/picture_options.h"
#include "render/video/tiling.h"

namespace clothsim::cli {

namespace {

using Clock = std::chrono::steady_clock;

// 4. The table, the warnings, the JSON and the breakdown.
void report_compare(const CompareRequest& o, const ComparePlan& p, const PipelineReport& report,
                    Clock::time_point wall_start) {
  print_summary(*p.model, report, p.look.color, p.summary_context());
  for (const ReferenceReport& ref : report.references)
    if (ref.result.divergence) {
      // The error colouring measures nothing after it: say so where a user looks, with the fix.
      std::fflush(stdout);
      std::fprintf(stderr,
                   "clothsim: warning: the reference lane %s @ %s s%s diverged at t = %.6g s: the error colouring "
                   "stops there; give --reference NAME@STEP with a smaller step or a stabler method\n",
                   ref.result.spec.name().c_str(), ref.result.spec.step_text.c_str(),
                   ref.label.empty() ? "" : (" (" + ref.label + ")").c_str(), ref.result.divergence->t);
    }
  if (!o.summary.empty()) write_compare_summary(o, p, report);
  if (!quiet())
    print_breakdown(*p.grid, p.legend_width, report, std::chrono::duration<double>(Clock::now() - wall_start).count());
}

int compare_command(const CompareRequest& o) {
  const auto wall_start = Clock::now();
  install_interrupt_handler();  // first: Ctrl-C during setup is then seen at the first frame
  const std::optional<ComparePlan> p = plan_compare_part(o);
  if (!p) return kOk;  // a part with no lane (more parts than lanes)
  const PipelineReport report = run_compare(o, *p);
  report_compare(o, *p, report, wall_start);
  return kOk;
}

}  // namespace

void add_compare_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<CompareRequest>();
  CLI::App* sub = app.add_subcommand("compare",
      "Run one scene with several integrators (or one at several steps) at once and show them side by\n"
      "side: a tiled, labelled MP4 (--video), each lane's PNGs (--frames), a contact sheet (--sheet),\n"
      "and a summary table of cost and divergence on stdout. By default the lanes are matched on cost\n"
      "(--match), each tile is coloured by its error against a reference (the adaptive dopri5 on a smooth\n"
      "scene; RK4 at a quarter of the smallest step, or at its predicted stable step if smaller, where\n"
      "contacts are projected) and shows its work (--overlay-cost cpu adds its CPU time), and a\n"
      "finite but implausible lane is marked WRONG. Divergence is a result here (exit 0).\n"
      "Without --video, --frames or --export, the lanes stop at the last --times or --still (at 1 s at least when\n"
      "the colour scale is taken from the first second's data; --color-range LO,HI avoids that).\n"
      "Beneath the table, each lane's field in numbers, with the frames they cover.");
  add_scene_options(sub, o->scene, /*single_run=*/false);
  add_gl_options(sub, o->gl);
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  add_picture_look_options(sub, o->look, /*compare=*/true);
  sub->add_option("--summary", o->summary, "Write what each lane did as JSON (docs/summary.md)")->type_name("FILE.json");
  add_frames_shard_option(sub, o->shard);
  sub->add_option("--integrators", o->integrators,
                  "Lanes, one tile each: NAME[@STEP],... (rk4@1e-4,rk4@4e-4,implicit_euler@1/60; the same integrator\n"
                  "may appear at several steps; without @STEP, --dt or the scene's dt), or course: the course's four\n"
                  "(explicit Euler, the one-iteration fixed-point implicit, midpoint, RK4); implicit_euler_fixed_point[@STEP]\n"
                  "is the course's implicit alone")
      ->capture_default_str();
  sub->add_option("--match", o->match,
                  "Each lane's step, for lanes without @STEP or --dt: cost (default: the step where its work per\n"
                  "simulated second, in spring-pass equivalents, equals the cheapest lane's at the scene's step), error TOL\n"
                  "(the largest step within TOL metres of the reference at every frame, by bisection) or none (the scene's)")
      ->expected(1, 2)
      ->type_name("cost|error TOL|none");
  sub->add_option("--vary", o->vary,
                  "Lanes by a parameter's value, labelled 'ks = 2e4': KEY a dotted scene path, a glob over the spring\n"
                  "types (cloth.springs.*.stiffness) or ks / kd (every spring type's stiffness / damping). With\n"
                  "--integrators, a grid: a row per integrator, a column per value; without, the scene's integrator.\n"
                  "The lanes run at one step unless --match cost is given; colour by strain unless --color says otherwise")
      ->type_name("KEY=V1,V2,...");
  sub->add_option("--layout", o->layout,
                  "COLUMNSxROWS: 2x2, 4x1 (side by side), 1x4 (stacked), Nx1, 1xN or auto")
      ->capture_default_str();
  sub->add_option("--video", o->video, "Write the tiled clip as H.264 MP4")->type_name("FILE.mp4");
  add_export_option(sub, o->export_path);
  sub->add_option("--frames", o->frames_dir,
                  "Keep every lane's PNGs in DIR/<integrator>/frame_00000.png... (DIR/<integrator>@<step>/ when an\n"
                  "integrator has several lanes)")
      ->type_name("DIR");
  sub->add_option("--dt", o->dt,
                  "Step for the lanes without @STEP: all (S), per integrator (rk4=2e-4,implicit_euler=1/60) or "
                  "both (1e-4,rk4=2e-4); a number or a fraction of a second; default: the scene's dt")
      ->type_name("S|NAME=S,...");
  sub->add_option("--sheet", o->sheet, "Write a contact sheet: one row per lane, one column per --times")
      ->type_name("FILE.png");
  sub->add_option("--times", o->times, "Contact-sheet columns, simulated seconds, increasing")
      ->type_name("T1,T2,...");
  sub->add_option("--still", o->still_t, "Write the tiled picture at time T (s) to -o/--output")->type_name("T");
  sub->add_option("-o,--output,--out", o->still_out, "PNG file for --still")->type_name("FILE.png");
  add_picture_options(sub, o->scene, "the whole grid", "--frames and --video");
  sub->add_option("--crf", o->crf, "Video quality, x264 CRF 0 (lossless) .. 51")->capture_default_str();
  sub->add_option("--preset", o->preset, "x264 preset (ultrafast .. veryslow)")->capture_default_str();
  sub->callback([o, sub, &command] {
    o->integrators_given = sub->get_option("--integrators")->count() > 0;
    o->match_given = sub->get_option("--match")->count() > 0;
    command = [o] { return compare_command(*o); };
  });
}

}  // namespace clothsim::cli
