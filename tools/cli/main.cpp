// clothsim: see and measure how time integrators trade speed for accuracy.
// Dispatches to one subcommand and maps failures to the exit codes of the CLI contract:
// 0 success, 1 runtime failure (I/O, GL, encoder), 2 bad usage or bad scene, 3 diverged,
// 4 an implicit step did not converge (run --strict), 130 / 143 / 129 stopped by SIGINT /
// SIGTERM / SIGHUP (after removing temporaries and saying what was kept).
#include <algorithm>
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "clip/common/memory_budget.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "scene/echo.h"
#include "scene/scene_parser.h"
#include "core/integrators/integrator_kind.h"

using namespace clothsim;
using namespace clothsim::cli;

namespace {
// Every error is one line on stderr, whatever a library or the user's text put in it. The
// messages built here already echo the user's values through excerpt() (escaped once, cut to
// 80 characters); one_line() is the last guard for the rest (CLI11's messages echo an option's
// value whole, a library's may hold a newline) and leaves those escapes as they are.
void say(const std::string& message) { std::fprintf(stderr, "clothsim: %s\n", one_line(message).c_str()); }

// A failure met because a signal arrived (an open or write it broke off: EINTR, a FIFO with no
// reader) is the signal's stop: said as one and exit 128 + N, the failure in brackets.
int failed(const std::string& message) {
  if (!interrupted()) {
    say(message);
    return kRuntimeFailure;
  }
  say(message.rfind("stopped by ", 0) == 0 ? message
                                           : std::string("stopped by ") + interrupt_signal_name() + " (" + message + ")");
  return 128 + interrupt_signal();
}

// The first word, when it is no command: "unknown command 'comapre' (did you mean compare?)"
// where CLI11 says only "A subcommand is required"; "" when it is one, or an option.
std::string unknown_command(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  const std::string typed = argv[1];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == typed) return "";
    names.push_back(sub->get_name());
  }
  const std::string near = nearest_name(typed, names);
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return "unknown command " + in_quotes(typed) + " (" + (near.empty() ? "" : "did you mean " + near + "? ") +
         "the commands: " + list + ")";
}

// An option the command does not take but one of its own spells with a letter more or less
// (--integrator to compare, which takes --integrators): " (did you mean --integrators?)".
std::string option_hint(const CLI::App& app, int argc, char** argv) {
  const std::vector<CLI::App*> used = app.get_subcommands();
  if (used.empty()) return "";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = std::string(argv[i]).substr(0, std::string(argv[i]).find('='));
    if (arg.rfind("--", 0) != 0 || arg.size() < 4) continue;
    const std::string typed = arg.substr(2);
    bool known = false;
    std::string near;
    for (const CLI::Option* option : used.front()->get_options()) {
      for (const std::string& name : option->get_lnames()) {
        known = known || name == typed;
        const bool one_apart = name.size() == typed.size() + 1 ? name.compare(0, typed.size(), typed) == 0
                               : typed.size() == name.size() + 1 ? typed.compare(0, name.size(), name) == 0 : false;
        if (one_apart) near = name;
      }
    }
    if (!known && !near.empty()) return " (did you mean --" + near + "?)";
  }
  return "";
}
}  // namespace

// Before the shared libraries' constructors too (Mesa's LLVM takes tens of milliseconds to
// start): an executable's .preinit_array runs ahead of every other initialiser, so a signal
// from the first instant after loading is answered, not met by the default action.
static void install_early(int, char**, char**) { install_signal_handlers(); }
[[gnu::used, gnu::section(".preinit_array")]] static void (*const early_signals)(int, char**, char**) = install_early;

int main(int argc, char** argv) {
  install_signal_handlers();  // before any work: a signal at any moment is answered (docs/outputs.md)
  // Past a file-size limit (ulimit -f, a batch scheduler's quota) the kernel would kill us
  // with SIGXFSZ mid-write; ignored, the write fails with EFBIG and the output is dropped
  // with one line ("cannot write clip.mp4: File too large"), exit 1, like a full disk.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{
      "clothsim " CLOTHSIM_VERSION
      " - a headless mass-spring cloth simulator that shows and measures how time\n"
      "integrators trade speed for accuracy. Scenes are YAML (see docs/scenes.md)."};
  app.require_subcommand(1);
  std::string integrators = "Integrators (--integrator NAME, scene key integrator:):\n";
  std::size_t width = 0;
  for (const IntegratorInfo& info : integrator_registry()) width = std::max(width, info.name.size() + 2);
  for (const IntegratorInfo& info : integrator_registry()) {
    std::string name(info.name);
    name.resize(width, ' ');
    integrators += "  " + name + std::string(info.description) + "\n";
  }
  app.footer(
      integrators + kExitCodesHelp +
      "`clothsim SUBCOMMAND --help` for each command.\n"
      "Docs: README.md, docs/scenes.md (every scene key), docs/integrators.md.");
  app.set_version_flag("--version", "clothsim " CLOTHSIM_VERSION);
  Command command;
  add_run_command(app, command);
  add_compare_command(app, command);
  add_bench_command(app, command);
  add_converge_command(app, command);
  add_stability_command(app, command);
  add_validate_command(app, command);
  add_encode_command(app, command);
  add_imgdiff_command(app, command);
  add_golden_command(app, command);
  add_merge_command(app, command);
  add_cache_command(app, command);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with code 0; everything else is bad usage.
    if (e.get_exit_code() == 0) return app.exit(e);
    if (const std::string unknown = unknown_command(app, argc, argv); !unknown.empty()) {
      say(unknown);
      return kBadInput;
    }
    say(e.what() + option_hint(app, argc, argv));
    return kBadInput;
  }
  try {
    return exit_code_after(command());
  } catch (const SceneError& e) {
    say(e.what());
    return kBadInput;
  } catch (const UsageError& e) {
    say(e.what());
    return kBadInput;
  } catch (const RuntimeFailure& e) {
    // A command stopped by a signal says so as a RuntimeFailure; the exit code tells a
    // script it was stopped, not that it failed.
    return failed(e.what());
  } catch (const RenderError& e) {
    return failed(std::string("render: ") + e.what());
  } catch (const PngError& e) {
    return failed(e.what());
  } catch (const OutputFileError& e) {
    return failed(e.what());
  } catch (const std::bad_alloc&) {  // past what the estimate foresaw (memory_budget.h)
    const std::optional<double> as = address_space_limit();
    say(std::string("out of memory") +
        (as ? " under the address-space limit (ulimit -v " + format_bytes(*as) + ")" : std::string()) +
        "; the files already written stay, nothing else; use fewer particles or a smaller picture" +
        (as ? ", or raise ulimit -v" : ""));
    return kRuntimeFailure;
  } catch (const std::exception& e) {
    say(std::string("internal error: ") + e.what());
    return kRuntimeFailure;
  }
}
