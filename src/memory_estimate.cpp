#include "memory_estimate.h"

namespace clothsim {

namespace {
constexpr double kModelPerParticle = 64, kModelPerSpring = 40;
constexpr double kExplicitPerParticle = 192;
constexpr double kImplicitPerParticle = 256, kImplicitPerSpring = 128;
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
  return kModelPerParticle * particles + kModelPerSpring * static_cast<double>(spring_count(scene.cloth)) +
         kPerSphere * static_cast<double>(scene.spheres.size());
}

double run_bytes(const SceneDef& scene, IntegratorKind kind) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  double bytes = kExplicitPerParticle * particles;
  if (kind == IntegratorKind::ImplicitEuler)
    bytes += kImplicitPerParticle * particles + kImplicitPerSpring * static_cast<double>(spring_count(scene.cloth));
  return bytes;
}

}  // namespace clothsim
