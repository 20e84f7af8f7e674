// Each registry row states its method's memory (method_memory.h): what the method keeps beyond
// the explicit family's state, growing as its arrays do.
#include "core/integrators/method_memory.h"

#include <gtest/gtest.h>

#include "core/integrators/integrator_kind.h"

namespace clothsim {
namespace {

MemorySizes sheet(double particles) { return {particles, 6.0 * particles, particles + 1.0, SolverDefs{}}; }

TEST(MethodMemory, EveryRowStatesItsMemoryAndItGrowsWithTheCloth) {
  for (const IntegratorInfo& info : integrator_registry()) {
    ASSERT_NE(info.memory, nullptr) << info.name;
    // (both from 32 x 32 on, where implicit Euler's auto takes block Jacobi alone)
    const MethodMemory small = info.memory(sheet(2000)), large = info.memory(sheet(200000));
    EXPECT_GT(small.run, 0.0) << info.name;
    EXPECT_GT(large.run, 90.0 * small.run) << info.name;  // at least linear in the particles
    EXPECT_GT(large.final_state, 90.0 * small.final_state) << info.name;
  }
}

TEST(MethodMemory, MethodsThatKeepMoreCountMore) {
  const MemorySizes n = sheet(65536);
  const double explicit_run = integrator_info(IntegratorKind::ExplicitEuler).memory(n).run;
  EXPECT_EQ(integrator_info(IntegratorKind::SymplecticEuler).memory(n).run, explicit_run);
  EXPECT_GT(integrator_info(IntegratorKind::Midpoint).memory(n).run, explicit_run);  // the half-step state
  EXPECT_GT(integrator_info(IntegratorKind::Rk4).memory(n).run,
            integrator_info(IntegratorKind::Midpoint).memory(n).run);  // four stages
  // implicit_euler's Newton system and warm start; PD's prefactored matrix.
  EXPECT_GT(integrator_info(IntegratorKind::ImplicitEuler).memory(n).run, 4.0 * explicit_run);
  EXPECT_GT(integrator_info(IntegratorKind::ImplicitEuler).memory(n).final_state,
            integrator_info(IntegratorKind::Rk4).memory(n).final_state);
  EXPECT_GT(integrator_info(IntegratorKind::ProjectiveDynamics).memory(n).run, 10.0 * explicit_run);
}

// VBD's accelerated iterations keep two more iterates: 48 B a particle.
TEST(MethodMemory, VbdsAcceleratedIterationsCountTwoMoreIterates) {
  MemorySizes n = sheet(1000);
  const double plain = vbd_memory(n).run;
  n.solvers.vbd.chebyshev_rho = 0.9;
  EXPECT_DOUBLE_EQ(vbd_memory(n).run - plain, 48.0 * 1000);
}

}  // namespace
}  // namespace clothsim
