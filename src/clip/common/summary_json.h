// --summary FILE.json: what run, compare, bench and stability did, for scripts (docs/summary.md
// has the schema). Every command writes the same envelope and one object per lane (one run of
// one integrator at one step), with the same names for the same quantities; a command adds
// its own keys beside them. Written whole or not at all (AtomicFile).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/integrators/integrator_kind.h"
#include "core/run/simulation.h"

namespace clothsim::clip {

// A JSON object built key by key, each value serialised as it is added (keys in that order).
class JsonObject {
 public:
  JsonObject& number(const std::string& key, double value);  // non-finite: null
  JsonObject& number(const std::string& key, std::optional<double> value);
  JsonObject& integer(const std::string& key, std::int64_t value);
  JsonObject& integer(const std::string& key, std::optional<std::int64_t> value);
  JsonObject& text(const std::string& key, const std::string& value);
  JsonObject& boolean(const std::string& key, bool value);
  JsonObject& object(const std::string& key, const JsonObject& value);
  JsonObject& array(const std::string& key, const std::vector<JsonObject>& values);
  JsonObject& append(const JsonObject& other);  // other's members after these
  std::string dump(int indent = 0) const;  // pretty-printed, two spaces a level
  // An object serialised earlier by dump() (a sharded study's lane, kept on disk), placed
  // as it was: `clothsim merge` writes the summary one process writes.
  static JsonObject from_dump(std::string dumped);
 private:
  std::string dumped_;  // from_dump's text; empty for an object built key by key
  struct Member {
    std::string key;
    enum Kind { kScalar, kObject, kArray } kind = kScalar;
    std::string scalar;                // serialised, for kScalar
    std::vector<JsonObject> children;  // one for kObject, any number for kArray
  };
  JsonObject& scalar(const std::string& key, std::string serialised);
  std::vector<Member> members_;
};

// The common keys of a lane: scene, integrator, dt, steps, force_evaluations, cpu_seconds,
// newton_iterations, cg_iterations, unconverged_steps, diverged_at (null unless it diverged).
JsonObject lane_json(const std::string& scene, IntegratorKind kind, double dt, const RunTotals& totals,
                     std::optional<double> diverged_at);
// The same keys for work that is not one run (a stability search: many trial runs): the
// counters null, cpu_seconds summed over the trials.
JsonObject lane_json_without_counts(const std::string& scene, IntegratorKind kind, std::optional<double> dt,
                                    double cpu_seconds);

// Writes {"clothsim": VERSION, "command": ..., "source": ..., <extra keys>, "lanes": [...]}.
void write_summary(const std::string& path, const std::string& command, const std::string& source,
                   const std::vector<JsonObject>& lanes, const JsonObject& extra = {});

}  // namespace clothsim::clip
