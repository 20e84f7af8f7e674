#include "summary_json.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "cli_common.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

}  // namespace

JsonObject& JsonObject::scalar(const std::string& key, std::string serialised) {
  members_.push_back({key, Member::kScalar, std::move(serialised), {}});
  return *this;
}

JsonObject& JsonObject::number(const std::string& key, double value) {
  if (!std::isfinite(value)) return scalar(key, "null");  // JSON has no NaN or infinity
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", value);  // reads back bit-identical
  return scalar(key, buf);
}
JsonObject& JsonObject::number(const std::string& key, std::optional<double> value) {
  return value ? number(key, *value) : scalar(key, "null");
}
JsonObject& JsonObject::integer(const std::string& key, std::int64_t value) {
  return scalar(key, std::to_string(value));
}
JsonObject& JsonObject::integer(const std::string& key, std::optional<std::int64_t> value) {
  return value ? integer(key, *value) : scalar(key, "null");
}
JsonObject& JsonObject::text(const std::string& key, const std::string& value) { return scalar(key, quoted(value)); }
JsonObject& JsonObject::boolean(const std::string& key, bool value) { return scalar(key, value ? "true" : "false"); }
JsonObject& JsonObject::object(const std::string& key, const JsonObject& value) {
  members_.push_back({key, Member::kObject, {}, {value}});
  return *this;
}
JsonObject& JsonObject::array(const std::string& key, const std::vector<JsonObject>& values) {
  members_.push_back({key, Member::kArray, {}, values});
  return *this;
}

JsonObject& JsonObject::append(const JsonObject& other) {
  members_.insert(members_.end(), other.members_.begin(), other.members_.end());
  return *this;
}

JsonObject JsonObject::from_dump(std::string dumped) {
  JsonObject o;
  while (!dumped.empty() && (dumped.back() == '\n' || dumped.back() == ' ')) dumped.pop_back();
  o.dumped_ = std::move(dumped);
  return o;
}

std::string JsonObject::dump(int indent) const {
  if (!dumped_.empty()) {  // dumped at indent 0: each later line moves in by this indent
    std::string out;
    for (const char c : dumped_) out += c == '\n' ? "\n" + std::string(2 * indent, ' ') : std::string(1, c);
    return out;
  }
  if (members_.empty()) return "{}";
  const std::string pad(2 * (indent + 1), ' '), close(2 * indent, ' ');
  std::string out = "{\n";
  for (std::size_t i = 0; i < members_.size(); ++i) {
    const Member& m = members_[i];
    out += pad + quoted(m.key) + ": ";
    if (m.kind == Member::kScalar) {
      out += m.scalar;
    } else if (m.kind == Member::kObject) {
      out += m.children.front().dump(indent + 1);
    } else if (m.children.empty()) {
      out += "[]";
    } else {
      out += "[\n";
      for (std::size_t k = 0; k < m.children.size(); ++k)
        out += pad + "  " + m.children[k].dump(indent + 2) + (k + 1 < m.children.size() ? ",\n" : "\n");
      out += pad + "]";
    }
    out += i + 1 < members_.size() ? ",\n" : "\n";
  }
  return out + close + "}";
}

JsonObject lane_json(const std::string& scene, IntegratorKind kind, double dt, const RunTotals& totals,
                     std::optional<double> diverged_at) {
  JsonObject lane;
  lane.text("scene", scene)
      .text("integrator", std::string(integrator_name(kind)))
      .number("dt", dt)
      .integer("steps", totals.steps)
      .integer("force_evaluations", totals.force_evals)
      .number("cpu_seconds", totals.cpu_seconds)
      .integer("newton_iterations", totals.newton_iterations)
      .integer("cg_iterations", totals.cg_iterations)
      .integer("factorizations", totals.factorizations)
      .integer("unconverged_steps", totals.unconverged_steps)
      .number("diverged_at", diverged_at);
  return lane;
}

JsonObject lane_json_without_counts(const std::string& scene, IntegratorKind kind, std::optional<double> dt,
                                    double cpu_seconds) {
  const std::optional<std::int64_t> none;
  JsonObject lane;
  lane.text("scene", scene)
      .text("integrator", std::string(integrator_name(kind)))
      .number("dt", dt)
      .integer("steps", none)
      .integer("force_evaluations", none)
      .number("cpu_seconds", cpu_seconds)
      .integer("newton_iterations", none)
      .integer("cg_iterations", none)
      .integer("factorizations", none)
      .integer("unconverged_steps", none)
      .number("diverged_at", std::optional<double>());
  return lane;
}

void write_summary(const std::string& path, const std::string& command, const std::string& source,
                   const std::vector<JsonObject>& lanes, const JsonObject& extra) {
  JsonObject root;
  root.text("clothsim", CLOTHSIM_VERSION).text("command", command).text("source", source);
  root.append(extra).array("lanes", lanes);
  AtomicFile file(path);
  std::fputs(root.dump().c_str(), file.stream());
  std::fputs("\n", file.stream());
  file.commit();
}

}  // namespace clothsim::clip
