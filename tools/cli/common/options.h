// The options every subcommand shares, bound to CLI11: the values they fill are src/clip's
// (SceneOptions, GlOptions, PictureOptions...), parsed and checked there; only the binding of
// flags to those values lives here, so src/clip does not depend on CLI11.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "clip/common/gl_options.h"
#include "clip/common/install_paths.h"
#include "clip/common/lanes.h"
#include "clip/common/memory_budget.h"
#include "clip/common/progress.h"
#include "clip/common/scene_options.h"
#include "clip/compare/compare_shard.h"
#include "clip/frames/export_output.h"
#include "clip/frames/picture_options.h"
#include "clip/studies/study_shard.h"

namespace clothsim::clip {

// Declares --gl and --verbose on `sub` (GlOptions).
void add_gl_options(CLI::App* sub, GlOptions& options);

// Declares --max-memory SIZE on `sub`, parsed into `limit` (bytes).
void add_max_memory_option(CLI::App* sub, std::optional<double>& limit);

// Declares --progress and --quiet on `sub`; they set the process-wide settings below.
void add_progress_options(CLI::App* sub);

// Declares -n/--no-overwrite on `sub` (set_no_overwrite, cli_common.h).
void add_no_overwrite_option(CLI::App* sub);

// Declares SCENE, --set, --duration (its help saying `duration_default`) and --max-memory;
// --integrator and --dt only when `single_run`.
void add_scene_options(CLI::App* sub, SceneOptions& options, bool single_run,
                       const std::string& duration_default = "the scene's duration");

// Declares --width, --height and --fps (run and compare alike): the scene's render.width,
// render.height and render.fps, overridden. `size_of` says what the size is of, `frames_of`
// which outputs the frame rate paces.
void add_picture_options(CLI::App* sub, SceneOptions& options, const std::string& size_of,
                         const std::string& frames_of);

// Declares compare's --shard I/N on `sub` (compare_shard.h: a part of the frames).
void add_frames_shard_option(CLI::App* sub, std::string& shard);

// --export PATH on `sub` (its help names the formats).
void add_export_option(CLI::App* sub, std::string& path);

// Declares the picture's look (--color, --color-range, --overlay, --inset, --antialias...) on
// `sub`; `compare`: colouring defaults to error (against the reference lane) when the scene says nothing.
void add_picture_look_options(CLI::App* sub, PictureOptions& options, bool compare);

// Declares a study's --shard I/N on `sub` (study_shard.h).
void add_shard_option(CLI::App* sub, std::string& shard);

}  // namespace clothsim::clip
