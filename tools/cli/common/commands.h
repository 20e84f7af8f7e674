// The subcommands. Each add_*_command() declares its options on `app` and, when the
// subcommand is chosen, sets `command` to the function main() then runs. Each returns an
// exit code of the CLI contract (cli_common.h) or throws UsageError / RuntimeFailure /
// SceneError, which main() turns into one line on stderr and the matching code.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace clothsim::clip {}

namespace clothsim::cli {

// The commands call src/clip's work (the library under both front ends) by its plain names.
using namespace clothsim::clip;

using Command = std::function<int()>;

void add_run_command(CLI::App& app, Command& command);
void add_validate_command(CLI::App& app, Command& command);
void add_compare_command(CLI::App& app, Command& command);
void add_encode_command(CLI::App& app, Command& command);
void add_imgdiff_command(CLI::App& app, Command& command);
void add_bench_command(CLI::App& app, Command& command);
void add_stability_command(CLI::App& app, Command& command);
void add_converge_command(CLI::App& app, Command& command);
void add_golden_command(CLI::App& app, Command& command);
void add_merge_command(CLI::App& app, Command& command);  // studies/cmd_merge.cpp
void add_cache_command(CLI::App& app, Command& command);  // cache/cmd_cache.cpp

}  // namespace clothsim::cli
