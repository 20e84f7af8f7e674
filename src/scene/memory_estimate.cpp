#include "memory_estimate.h"

#include <algorithm>
#include <cmath>

namespace clothsim {

namespace {
// The Model's arrays per particle: mass and inverse mass 16 B, gravity flag 1 B, position and
// velocity 48 B, two triangles 24 B (89 B, rounded up); per spring two indices, rest length,
// stiffness, damping and type (33 B, rounded up); per scripted action (TimedAction) 48 B.
constexpr double kModelPerParticle = 96, kModelPerSpring = 40, kPerAction = 64;
constexpr double kExplicitPerParticle = 192;
constexpr double kRk4ExtraPerParticle = 104;  // its stages' scratch beyond the explicit family's
constexpr double kFinalStatePerParticle = 64;  // a kept copy of x, v and inverse masses
constexpr double kImplicitPerParticle = 480, kImplicitPerSpring = 144;
constexpr double kPerSphere = 4096;  // measured 3.9 kB, mostly the YAML tree of its entry
// implicit_euler's sparse factor, when a step needs it: L's 3x3 blocks (76 B each) number
// 27, 49, 69, 88 and 116 per particle at 25², 64², 128², 256² and 300² (AMD on the grid), so
// 8 log2(P) per particle bounds them; never more than the solver's cap (implicit_euler.cpp).
constexpr double kFactorBlockBytes = 80, kMaxFactorBytes = 512.0 * 1024 * 1024;
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

double run_bytes(const SceneDef& scene, IntegratorKind kind) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  double bytes = kExplicitPerParticle * particles;
  if (kind == IntegratorKind::Rk4) bytes += kRk4ExtraPerParticle * particles;
  if (kind == IntegratorKind::ImplicitEuler) {
    bytes += kImplicitPerParticle * particles + kImplicitPerSpring * static_cast<double>(spring_count(scene.cloth));
    const double factor = kFactorBlockBytes * particles * 8.0 * std::log2(std::max(particles, 2.0));
    bytes += std::min(factor, kMaxFactorBytes);
  }
  return bytes;
}

double final_state_bytes(const SceneDef& scene) {
  const double bodies = static_cast<double>(scene.cloth.nx) * scene.cloth.ny + static_cast<double>(scene.spheres.size());
  return kFinalStatePerParticle * bodies;
}

}  // namespace clothsim
