#include "options.h"

#include "scene/echo.h"

namespace clothsim::clip {

// common/gl_options
void add_gl_options(CLI::App* sub, GlOptions& options) {
  sub->add_option("--gl", options.gl,
                  "OpenGL backend: auto (EGL, then OSMesa), egl, osmesa (default: $CLOTHSIM_GL, else auto)")
      ->check(CLI::IsMember({"auto", "egl", "osmesa"}))
      ->type_name("auto|egl|osmesa");
  sub->add_flag("--verbose", options.verbose, "Say which OpenGL backend, vendor and renderer draw the frames");
}

// common/memory_budget
void add_max_memory_option(CLI::App* sub, std::optional<double>& limit) {
  sub->add_option_function<std::string>(
         "--max-memory",
         [&limit](const std::string& text) {
           try {
             limit = max_memory_option(text);
           } catch (const UsageError& e) {
             throw CLI::ValidationError(e.what());
           }
         },
         "Refuse (exit 2, with the estimate) a run whose estimated peak memory exceeds SIZE "
         "(4G, 512M; default: half the physical memory)")
      ->type_name("SIZE");
}

// common/progress
void add_progress_options(CLI::App* sub) {
  sub->add_option_function<std::string>(
         "--progress",
         [](const std::string& v) {
           set_progress_mode(v == "always" ? ProgressMode::always : v == "never" ? ProgressMode::never
                                                                                 : ProgressMode::automatic);
         },
         "Progress on stderr: auto (a bar on a terminal, else nothing), always (else a line every 5 s, "
         "for logs), never (default: auto)")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->type_name("auto|always|never");
  sub->add_flag_function("--quiet", [](std::int64_t n) { set_quiet(n > 0); },
                         "Nothing on stderr but errors and warnings (no progress, no timings)");
}

void add_no_overwrite_option(CLI::App* sub) {
  sub->add_flag_function("-n,--no-overwrite", [](std::int64_t n) { set_no_overwrite(n > 0); },
                         "Refuse to replace an output file that exists (exit 2, before any work)");
}

// common/scene_options
void add_scene_options(CLI::App* sub, SceneOptions& o, bool single_run, const std::string& duration_default) {
  sub->add_option("scene", o.path, "Scene file (YAML; keys in docs/scenes.md), or a shipped scene's name (drape_smooth)")
      ->required()
      ->transform(CLI::Validator(
          [](std::string& arg) {
            arg = resolve_scene_argument(arg);
            return std::string();
          },
          "", "scene"));
  sub->add_option("--set", o.sets,
                  "Override a scene key by its dotted path, e.g. --set cloth.springs.shear.stiffness=1e5 "
                  "(repeatable; VALUE is YAML, so lists work: --set gravity=[0,-1.6,0])")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_option("--duration", o.duration, "Simulated time in s (default: " + duration_default + ")");
  add_max_memory_option(sub, o.max_memory);
  if (single_run) {
    sub->add_option("--integrator", o.integrator,
                    "The lane to run, NAME[@STEP][:N][:tol=T] (docs/cli.md, \"Lanes\"): " + lane_names_joined(" | ") +
                        "; vbd@1/60:10 is VBD at 1/60 s with 10 iterations (default: the scene's integrator)")
        ->type_name("LANE");
    // A step of one per frame is said as a fraction (--dt 1/60), which CLI11's double would refuse.
    sub->add_option_function<std::string>(
           "--dt",
           [&o](const std::string& text) {
             const std::optional<double> dt = parse_number_or_fraction(text);
             if (!dt) throw CLI::ValidationError("--dt: " + in_quotes(text) + " is not a number (or a fraction like 1/60)");
             o.dt = *dt;
           },
           "Time step in s, a number or a fraction (1/60) (default: the scene's dt)")
        ->type_name("S");
  }
}

void add_picture_options(CLI::App* sub, SceneOptions& o, const std::string& size_of, const std::string& frames_of) {
  sub->add_option("--width", o.width, "Width of " + size_of + " in pixels (default: the scene's render.width)")
      ->type_name("PX");
  sub->add_option("--height", o.height, "Height of " + size_of + " in pixels (default: the scene's render.height)")
      ->type_name("PX");
  sub->add_option("--fps", o.fps,
                  "Output frames per simulated second: " + frames_of + " (default: the scene's render.fps)")
      ->type_name("F");
}

// compare/compare_shard
void add_frames_shard_option(CLI::App* sub, std::string& shard) {
  sub->add_option("--shard", shard,
                  "With --frames only: render part K of N of the lanes (K/N), or 'auto' from a Slurm array task; "
                  "`clothsim encode` composes the parts' folders (docs/cluster.md)")
      ->type_name("K/N|auto");
}

// frames/export_output
void add_export_option(CLI::App* sub, std::string& path) {
  sub->add_option("--export", path,
                  "Write the cloth and spheres of every frame for Blender or ParaView: DIR/frame_%05d.obj "
                  "or .ply (a file per frame), NAME.pc2 (Point Cache 2 beside NAME.obj), NAME.pvd "
                  "(VTK .vtp per frame in NAME/); docs/cli.md")
      ->type_name("PATH");
}

// frames/picture_options
void add_picture_look_options(CLI::App* sub, PictureOptions& o, bool compare) {
  sub->add_option("--color", o.color,
                  std::string("Colour the cloth by a field on a logarithmic scale with a colour bar: checker (none),\n"
                              "error (distance from a reference lane run alongside, m), strain (|l/l0-1| of the\n"
                              "springs, averaged to particles) or speed (m/s). Default: the scene's render.color, else ") +
                      (compare ? "error" : "checker"))
      ->type_name("FIELD");
  sub->add_option("--color-range", o.color_range,
                  "The colour scale, fixed for the whole clip (default: from the data of the first second, printed)")
      ->type_name("LO,HI");
  sub->add_option("--reference", o.reference,
                  std::string(compare ? "The lane --color error and --inset energy measure against" : "The lane --color error measures against") +
                      " (default: on a smooth scene the adaptive dopri5 at tolerance 1e-7,\n"
                      "checked at 1e-8, or dopri5:tol=T; with projected contacts rk4 at a quarter of the smallest lane\n"
                      "step, or at rk4's predicted stable step where that is smaller, or NAME@STEP)")
      ->type_name("NAME[@STEP]");
  sub->add_flag("--no-reference-cache", o.no_reference_cache,
                "Compute the reference even when the cache holds it, and do not store it\n"
                "($XDG_CACHE_HOME/clothsim; `clothsim cache clear` empties it; docs/compare.md)");
  sub->add_option("--camera", o.camera, "auto: frame the cloth and spheres; scene: the scene's render.camera")
      ->type_name("auto|scene");
  sub->add_option("--overlay", o.overlay,
                  "Text on the pictures: full (time, force evaluations, banners), label (the lane only) or none "
                  "(default: the scene's render.overlay, full)")
      ->type_name("full|label|none");
  sub->add_option("--overlay-cost", o.overlay_cost,
                  "work: spring-pass equivalents per simulated s (docs/compare.md; the same on every run, so\n"
                  "the same command gives the same bytes); cpu: measured CPU ms per simulated s beside them\n"
                  "(differs from run to run; always in the printed table and --summary). Default: work")
      ->type_name("work|cpu");
  sub->add_option("--inset", o.inset,
                  compare ? "energy: a small graph in each tile of the lane's total energy minus the reference's, E - Eref, on\n"
                            "shared axes (E - E(0) with --vary)"
                          : "energy: a small graph of the energy change E - E(0) over time in the picture")
      ->capture_default_str()
      ->type_name("energy|none");
  sub->add_option("--antialias", o.antialias,
                  std::string("Smooth edges by msaa (the scene's render.msaa samples, else 4), fxaa (one sample, edges\n"
                              "smoothed on the CPU: cheaper on llvmpipe) or none. Default: the scene's render.antialias\n"
                              "or render.msaa, else ") +
                      (compare ? "fxaa" : "msaa"))
      ->type_name("msaa|fxaa|none");
}

// studies/study_shard
void add_shard_option(CLI::App* sub, std::string& shard) {
  sub->add_option("--shard", shard,
                  "Run part K of N of the study (K/N), or 'auto' from a Slurm array task; needs --csv F and "
                  "writes F.shard-K-of-N/ for `clothsim merge` (docs/cluster.md)")
      ->type_name("K/N|auto");
}

}  // namespace clothsim::clip
