// The Newton solve's records (newton_solve.h): the matrix-reuse phases and their transitions,
// and the trace, which goes only where the tool sends it and changes no number.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.h"
#include "core/implicit/newton_solve.h"
#include "core/simulation.h"
#include "scene/build_model.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::ImplicitEuler;

TEST(MatrixReuse, ATrialThatServesKeepsReuseAllowedAndTrusted) {
  MatrixReuse reuse;
  reuse.phase = MatrixReuse::Phase::Allowed;
  reuse.trusted = false;
  reuse.start_trial(2.0);
  EXPECT_EQ(reuse.phase, MatrixReuse::Phase::OnTrial);
  EXPECT_EQ(reuse.trial_from, 2.0);
  reuse.judge(true);
  EXPECT_EQ(reuse.phase, MatrixReuse::Phase::Allowed);
  EXPECT_TRUE(reuse.trusted);
  EXPECT_EQ(reuse.unserved, 0);
}

TEST(MatrixReuse, ATrialThatFailsBarsReuseAndIsNotChargedToTheBudget) {
  for (const bool judged : {true, false}) {
    MatrixReuse reuse;
    reuse.phase = MatrixReuse::Phase::Allowed;
    reuse.start_trial(1.0);
    if (judged) reuse.judge(false);
    else reuse.fail();  // no descent or no step
    EXPECT_EQ(reuse.phase, MatrixReuse::Phase::Barred);
    EXPECT_FALSE(reuse.allowed());
    EXPECT_FALSE(reuse.trusted);
    EXPECT_EQ(reuse.unserved, 1);
  }
}

TEST(NewtonTrace, GoesOnlyToTheSinkTheToolGivesAndChangesNoNumber) {
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml",
                                             {"dt=0.03333333333333333"}));
  State quiet = initial_state(model), traced = quiet;
  Workspace quiet_ws, traced_ws;
  std::vector<std::string> lines;
  traced_ws.newton_trace = [&lines](const char* line) { lines.emplace_back(line); };
  for (int n = 0; n < 10; ++n) {
    step(model, quiet, kKind, model.dt, quiet_ws);
    step(model, traced, kKind, model.dt, traced_ws);
  }
  EXPECT_EQ((quiet.x - traced.x).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((quiet.v - traced.v).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front().rfind("newton step 0 start:", 0), 0u) << lines.front();
  int starts = 0;
  for (const std::string& line : lines) starts += line.find(" start: held ") != std::string::npos;
  EXPECT_EQ(starts, 10);
}

}  // namespace
}  // namespace clothsim::testing
