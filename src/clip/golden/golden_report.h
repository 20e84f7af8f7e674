// What `golden check` says about each image, in one record that makes its report line, its
// CSV row (--csv) and its summary entry (--summary), so `clothsim merge` can rebuild, from
// the rows a sharded check journaled, the report one process prints (docs/cluster.md).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "clip/common/summary_json.h"

namespace clothsim::clip {

struct GoldenVerdict {
  std::size_t entry = 0;      // the manifest's goldens[ENTRY]
  std::string image;          // the golden's file name, "drape_t1500ms.png"
  double t = 0.0;             // s
  bool ok = false;
  double rms = -1.0;          // the comparison, when there was one (rms < 0: none)
  int max = 0;
  double over_fraction = 0.0;
  int threshold = 0;
  std::string problem;        // FAIL: what is wrong, in words
  std::string actual, diff;   // FAIL: the evidence written ("" when none)
};

// "ok    NAME  rms ..." or "FAIL  NAME  PROBLEM; actual: PATH, diff: PATH".
std::string golden_report_line(const GoldenVerdict& v);
// "golden: 3 of 4 images match (MANIFEST)".
std::string golden_tally(const std::vector<GoldenVerdict>& verdicts, const std::string& manifest);
// "goldens[2] (drape_rk4_t500ms.png), ..." for the images that failed; "" when none did.
std::string golden_failures(const std::vector<GoldenVerdict>& verdicts);

// The CSV: one row per image, in manifest order (golden_csv_row ends with a newline).
std::string golden_csv_header();
std::string golden_csv_row(const GoldenVerdict& v);
// A row back; throws std::runtime_error on a row that is not golden_csv_row's.
GoldenVerdict parse_golden_row(const std::string& row);

// --junit: JUnit XML as CI systems read it (GitLab, Jenkins, GitHub's reporters): one
// <testsuite> for the manifest, one <testcase> per entry (classname golden, name the entry's
// name), failed when any of its images failed, the failure's text each such image's problem and
// RMS; each diff image's path a property "attachment" and a [[ATTACHMENT|PATH]] line in
// system-out (Jenkins' and GitLab's spelling). `names` by entry index; `seconds` each entry's
// run, the testcase's time.
std::string golden_junit(const std::string& manifest, const std::vector<std::string>& names,
                         const std::vector<double>& seconds, const std::vector<GoldenVerdict>& verdicts);

// The summary's own keys: complete (true), images, matching.
JsonObject golden_summary_keys(const std::vector<GoldenVerdict>& verdicts);
// The summary's image object (an entry's lane lists its images).
JsonObject golden_image_json(const GoldenVerdict& v);

}  // namespace clothsim::clip
