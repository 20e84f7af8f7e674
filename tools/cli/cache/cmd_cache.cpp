// clothsim cache info|clear: the reference cache (study/reference_cache.h), where it is and what
// it holds, or emptied. compare's --no-reference-cache bypasses it for one run.
#include <cinttypes>
#include <cstdio>
#include <stdexcept>

#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "study/reference_cache.h"

namespace clothsim::cli {

void add_cache_command(CLI::App& app, Command& command) {
  CLI::App* sub = app.add_subcommand("cache", "The reference cache ($XDG_CACHE_HOME/clothsim): info or clear");
  auto action = std::make_shared<std::string>();
  sub->add_option("action", *action, "info: where it is, its entries and size; clear: remove every entry")
      ->required()
      ->check(CLI::IsMember({"info", "clear"}));
  sub->callback([&command, action] {
    command = [action] {
      analysis::ReferenceCacheSettings settings;
      try {
        settings = analysis::reference_cache_settings();
      } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
      }
      if (settings.dir.empty()) throw UsageError("cache: neither XDG_CACHE_HOME nor HOME is set: no cache folder");
      const analysis::ReferenceCache cache(settings);
      const bool clear = *action == "clear";
      const analysis::ReferenceCache::Contents c = clear ? cache.clear() : cache.contents();
      std::printf("%s: %s %ld entr%s, %.1f MB (cap %.0f MB, CLOTHSIM_REFERENCE_CACHE_MAX)\n", cache.dir().c_str(),
                  clear ? "removed" : "holds", c.entries, c.entries == 1 ? "y" : "ies", c.bytes / 1048576.0,
                  settings.max_bytes / 1048576.0);
      return 0;
    };
  });
}

}  // namespace clothsim::cli
