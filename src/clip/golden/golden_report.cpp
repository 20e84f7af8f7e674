#include "golden_report.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "clip/studies/study_common.h"
#include "clip/studies/study_shard.h"

namespace clothsim::clip {

std::string golden_report_line(const GoldenVerdict& v) {
  char text[200];
  if (v.ok) {
    std::snprintf(text, sizeof text, "ok    %s  rms %.3f, max %d, %.3f%% past %d", v.image.c_str(), v.rms, v.max,
                  100.0 * v.over_fraction, v.threshold);
    return text;
  }
  std::string line = "FAIL  " + v.image + "  " + v.problem;
  if (!v.actual.empty()) line += "; actual: " + v.actual;
  if (!v.diff.empty()) line += ", diff: " + v.diff;
  return line;
}

std::string golden_tally(const std::vector<GoldenVerdict>& verdicts, const std::string& manifest) {
  std::size_t ok = 0;
  for (const GoldenVerdict& v : verdicts) ok += v.ok ? 1 : 0;
  return "golden: " + std::to_string(ok) + " of " + std::to_string(verdicts.size()) + " images match (" + manifest + ")";
}

std::string golden_failures(const std::vector<GoldenVerdict>& verdicts) {
  std::string out;
  for (const GoldenVerdict& v : verdicts)
    if (!v.ok) out += (out.empty() ? "" : ", ") + ("goldens[" + std::to_string(v.entry) + "] (" + v.image + ")");
  return out;
}

std::string golden_csv_header() {
  return "entry,image,t,result,rms,max,over_fraction,threshold,problem,actual,diff";
}

std::string golden_csv_row(const GoldenVerdict& v) {
  const bool compared = v.rms >= 0.0;
  return std::to_string(v.entry) + "," + csv_text(v.image) + "," + csv_number(v.t) + "," + (v.ok ? "ok" : "FAIL") +
         "," + (compared ? csv_number(v.rms) : "") + "," + (compared ? std::to_string(v.max) : "") + "," +
         (compared ? csv_number(v.over_fraction) : "") + "," + std::to_string(v.threshold) + "," +
         csv_text(v.problem) + "," + csv_text(v.actual) + "," + csv_text(v.diff) + "\n";
}

GoldenVerdict parse_golden_row(const std::string& row) {
  const std::vector<std::string> c = csv_cells(row);
  if (c.size() != 11 || (c[3] != "ok" && c[3] != "FAIL"))
    throw std::runtime_error("not a golden check row: " + row.substr(0, 80));
  GoldenVerdict v;
  v.entry = std::strtoul(c[0].c_str(), nullptr, 10);
  v.image = c[1];
  v.t = std::strtod(c[2].c_str(), nullptr);
  v.ok = c[3] == "ok";
  if (!c[4].empty()) {
    v.rms = std::strtod(c[4].c_str(), nullptr);
    v.max = std::atoi(c[5].c_str());
    v.over_fraction = std::strtod(c[6].c_str(), nullptr);
  }
  v.threshold = std::atoi(c[7].c_str());
  v.problem = c[8];
  v.actual = c[9];
  v.diff = c[10];
  return v;
}

namespace {
// Text for an XML attribute or element: the five entities, and control characters (which
// XML 1.0 cannot hold) as '?'.
std::string xml(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') ? '?' : c;
    }
  }
  return out;
}
}  // namespace

std::string golden_junit(const std::string& manifest, const std::vector<std::string>& names,
                         const std::vector<double>& seconds, const std::vector<GoldenVerdict>& verdicts) {
  std::size_t failed_entries = 0;
  std::vector<std::vector<const GoldenVerdict*>> by_entry(names.size());
  for (const GoldenVerdict& v : verdicts)
    if (v.entry < by_entry.size()) by_entry[v.entry].push_back(&v);
  for (const auto& images : by_entry)
    failed_entries += std::any_of(images.begin(), images.end(), [](const GoldenVerdict* v) { return !v->ok; });
  double total = 0.0;
  for (double s : seconds) total += s;
  char head[256];
  std::snprintf(head, sizeof head, "  <testsuite name=\"golden\" tests=\"%zu\" failures=\"%zu\" errors=\"0\" skipped=\"0\" time=\"%.3f\"",
                names.size(), failed_entries, total);
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n" + std::string(head) +
                    " file=\"" + xml(manifest) + "\">\n";
  for (std::size_t i = 0; i < names.size(); ++i) {
    char time[32];
    std::snprintf(time, sizeof time, "%.3f", i < seconds.size() ? seconds[i] : 0.0);
    out += "    <testcase classname=\"golden\" name=\"" + xml(names[i]) + "\" file=\"" + xml(manifest) +
           "\" time=\"" + time + "\">\n";
    std::string problems, attachments, properties;
    std::size_t bad = 0;
    for (const GoldenVerdict* v : by_entry[i]) {
      if (v->ok) continue;
      ++bad;
      problems += golden_report_line(*v) + "\n";
      if (!v->diff.empty()) {
        properties += "        <property name=\"attachment\" value=\"" + xml(v->diff) + "\"/>\n";
        attachments += "[[ATTACHMENT|" + xml(v->diff) + "]]\n";
      }
    }
    if (!properties.empty()) out += "      <properties>\n" + properties + "      </properties>\n";
    if (bad > 0) {
      out += "      <failure message=\"" + xml(std::to_string(bad) + " of " + std::to_string(by_entry[i].size()) +
                                          " images differ from their golden") +
             "\" type=\"golden\">" + xml(problems) + "</failure>\n";
    }
    if (!attachments.empty()) out += "      <system-out>" + attachments + "</system-out>\n";
    out += "    </testcase>\n";
  }
  return out + "  </testsuite>\n</testsuites>\n";
}

JsonObject golden_summary_keys(const std::vector<GoldenVerdict>& verdicts) {
  std::int64_t ok = 0;
  for (const GoldenVerdict& v : verdicts) ok += v.ok ? 1 : 0;
  JsonObject keys;
  keys.boolean("complete", true).integer("images", static_cast<std::int64_t>(verdicts.size())).integer("matching", ok);
  return keys;
}

JsonObject golden_image_json(const GoldenVerdict& v) {
  const bool compared = v.rms >= 0.0;
  JsonObject image;
  image.text("image", v.image)
      .number("t", v.t)
      .text("result", v.ok ? "ok" : "FAIL")
      .number("rms", compared ? std::optional<double>(v.rms) : std::nullopt)
      .integer("max", compared ? std::optional<std::int64_t>(v.max) : std::nullopt)
      .number("over_fraction", compared ? std::optional<double>(v.over_fraction) : std::nullopt)
      .text("problem", v.problem);
  return image;
}

}  // namespace clothsim::clip
