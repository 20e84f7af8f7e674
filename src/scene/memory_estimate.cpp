#include "memory_estimate.h"

#include "core/integrators/integrator_kind.h"

namespace clothsim {

namespace {
// The Model's arrays per particle: mass and inverse mass 16 B, gravity flag 1 B, position and
// velocity 48 B, two triangles 24 B (89 B, rounded up); per spring two indices, rest length,
// stiffness, damping and type (33 B, rounded up); per scripted action (TimedAction) 48 B.
constexpr double kModelPerParticle = 96, kModelPerSpring = 40, kPerAction = 64;
constexpr double kPerSphere = 4096;  // measured 3.9 kB, mostly the YAML tree of its entry
}  // namespace

std::int64_t spring_count(const ClothDef& c) {
  const std::int64_t nx = c.nx, ny = c.ny;
  const auto positive = [](std::int64_t n) { return n > 0 ? n : 0; };
  std::int64_t springs = 0;
  if (c.structural) springs += positive(nx - 1) * ny + nx * positive(ny - 1);
  if (c.shear) springs += 2 * positive(nx - 1) * positive(ny - 1);
  if (c.bend) springs += positive(nx - 2) * ny + nx * positive(ny - 2);
  return springs;
}

double model_bytes(const SceneDef& scene) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  double actions = 0.0;  // the timeline: keyframes, pins and unpins
  for (const SphereDef& s : scene.spheres) actions += static_cast<double>(s.motion.size());
  for (const EventDef& e : scene.events) actions += static_cast<double>(e.pin.size() + e.unpin.size());
  return kModelPerParticle * particles + kModelPerSpring * static_cast<double>(spring_count(scene.cloth)) +
         kPerSphere * static_cast<double>(scene.spheres.size()) + kPerAction * actions;
}

namespace {
// The method's own terms are its registry row's (core/integrators/method_memory.h).
MethodMemory method_memory(const SceneDef& scene, IntegratorKind kind) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  const MemorySizes n{particles, static_cast<double>(spring_count(scene.cloth)),
                      particles + static_cast<double>(scene.spheres.size()), scene.solvers,
                      scene.implicit.preconditioner};
  return integrator_info(kind).memory(n);
}
}  // namespace

double run_bytes(const SceneDef& scene, IntegratorKind kind) { return method_memory(scene, kind).run; }

double final_state_bytes(const SceneDef& scene, IntegratorKind kind) {
  return method_memory(scene, kind).final_state;
}

}  // namespace clothsim
