// The scene reader's other blocks: spheres, collision, render settings and the solvers' options. See
// scene_reader.h.
#include "scene_reader.h"
#include "core/model/barrier_contacts.h"
#include "core/integrators/integrator_kind.h"
#include "view/vertex_fields.h"

namespace clothsim::scene_detail {

SphereDef Reader::sphere(const YAML::Node& n, const std::string& path) const {
  SphereDef s;
  expect_map(n, path, {"center", "radius", "kinematic", "mass", "gravity", "restitution",
                       "friction", "velocity", "motion"});
  optional(n, path, "center", [&](auto& v, auto& k) { s.center = vec3(v, k); });
  optional(n, path, "radius", [&](auto& v, auto& k) { s.radius = positive(v, k); });
  optional(n, path, "kinematic", [&](auto& v, auto& k) { s.kinematic = boolean(v, k); });
  optional(n, path, "mass", [&](auto& v, auto& k) {
    s.mass = mass(v, k);
    if (s.kinematic) fail(v, k, "a kinematic sphere has no mass (set kinematic: false for a dynamic one)");
  });
  optional(n, path, "gravity", [&](auto& v, auto& k) { s.gravity = boolean(v, k); });
  optional(n, path, "restitution", [&](auto& v, auto& k) { s.restitution = in_range(v, k, 0, 1); });
  optional(n, path, "friction", [&](auto& v, auto& k) { s.friction = non_negative(v, k); });
  optional(n, path, "velocity", [&](auto& v, auto& k) { s.velocity = vec3(v, k); });
  optional(n, path, "motion", [&](auto& v, auto& k) {
    if (!s.kinematic) fail(v, k, "only a kinematic sphere follows scripted motion");
    if (!v.IsSequence()) fail(v, k, "expected a list of keyframes [{t: s, velocity: [x, y, z]}, ...]");
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string p = k + "." + std::to_string(i);
      expect_map(v[i], p, {"t", "velocity"});
      if (!v[i]["t"].IsDefined() || !v[i]["velocity"].IsDefined())
        fail(v[i], p, "a keyframe needs t and velocity");
      Keyframe kf{non_negative(v[i]["t"], p + ".t"), vec3(v[i]["velocity"], p + ".velocity")};
      if (!s.motion.empty() && kf.t < s.motion.back().t)
        fail(v[i]["t"], p + ".t", "keyframes must be in increasing time");
      s.motion.push_back(kf);
    }
  });
  return s;
}

// The scene's own integrator must take the contact model (lanes are checked where they run).
CollisionDef Reader::collision(const YAML::Node& n, const std::string& path, IntegratorKind integrator) const {
  CollisionDef c;
  expect_map(n, path, {"model", "margin", "sphere_sphere", "sphere_restitution", "barrier_distance",
                       "barrier_stiffness", "friction_velocity"});
  optional(n, path, "model", [&](auto& v, auto& k) {
    const std::string m = string(v, k);
    if (m == "projection") c.model = ContactModel::Projection;
    else if (m == "barrier") c.model = ContactModel::Barrier;
    else fail(v, k, "unknown contact model " + in_quotes(m) + " (expected projection or barrier)");
  });
  optional(n, path, "margin", [&](auto& v, auto& k) { c.margin = non_negative(v, k); });
  optional(n, path, "sphere_sphere", [&](auto& v, auto& k) { c.sphere_sphere = boolean(v, k); });
  optional(n, path, "sphere_restitution", [&](auto& v, auto& k) { c.sphere_restitution = in_range(v, k, 0, 1); });
  optional(n, path, "barrier_distance", [&](auto& v, auto& k) { c.barrier_distance = positive(v, k); });
  optional(n, path, "barrier_stiffness", [&](auto& v, auto& k) { c.barrier_stiffness = positive(v, k); });
  optional(n, path, "friction_velocity", [&](auto& v, auto& k) { c.friction_velocity = positive(v, k); });
  const std::string refused = barrier_refusal(integrator);
  if (c.model == ContactModel::Barrier && !refused.empty()) fail(n["model"], path + ".model", refused);
  return c;
}

RenderDef Reader::render(const YAML::Node& n, const std::string& path) const {
  RenderDef r;
  expect_map(n, path, {"width", "height", "fps", "camera", "color", "overlay", "draw_springs", "draw_particles",
                       "samples", "msaa", "antialias"});
  optional(n, path, "width", [&](auto& v, auto& k) { r.width = int_in_range(v, k, RenderDef::kMinSize, RenderDef::kMaxSize); });
  optional(n, path, "height", [&](auto& v, auto& k) { r.height = int_in_range(v, k, RenderDef::kMinSize, RenderDef::kMaxSize); });
  optional(n, path, "fps", [&](auto& v, auto& k) {
    r.fps = in_range(v, k, 0.0, RenderDef::kMaxFps, true);
    r.fps_given = true;
  });
  optional(n, path, "draw_springs", [&](auto& v, auto& k) { r.draw_springs = boolean(v, k); });
  optional(n, path, "draw_particles", [&](auto& v, auto& k) { r.draw_particles = boolean(v, k); });
  optional(n, path, "samples", [&](auto& v, auto& k) {
    r.samples = int_in_range(v, k, 1, 16);
    r.samples_given = true;
  });
  // msaa: 0 (none), 2, 4 or 8 samples; the older `samples` (1 = none) says the same thing.
  optional(n, path, "msaa", [&](auto& v, auto& k) {
    if (n["samples"].IsDefined()) fail(v, k, "give msaa or samples, not both");
    const int m = integer(v, k);
    if (m != 0 && m != 2 && m != 4 && m != 8)
      fail(v, k, "value " + excerpt(v.Scalar()) + " is not one of 0, 2, 4, 8");
    r.samples = m == 0 ? 1 : m;
    r.samples_given = true;
  });
  // antialias: msaa (render.msaa's samples, 4 unless given), fxaa (one sample, edges smoothed
  // on the CPU) or none. A sample count says msaa (more than one sample: samples 2 to 16, msaa
  // 2, 4 or 8) or none (samples 1, msaa 0) by itself: given with antialias, it must say the
  // same, and fxaa takes none. The message says what the key that gave the count allows.
  optional(n, path, "antialias", [&](auto& v, auto& k) {
    const std::string a = string(v, k);
    if (a != "msaa" && a != "fxaa" && a != "none")
      fail(v, k, "unknown antialiasing " + in_quotes(a) + " (expected msaa, fxaa or none)");
    const bool agrees = a == "msaa" ? r.samples > 1 : a == "none" && r.samples == 1;
    if (r.samples_given && !agrees) {
      const bool by_msaa = n["msaa"].IsDefined();
      const std::string count = std::string(by_msaa ? "msaa" : "samples") + ": " + n[by_msaa ? "msaa" : "samples"].Scalar();
      const std::string why = a == "msaa"   ? (by_msaa ? "msaa needs msaa: 2, 4 or 8" : "msaa needs samples: 2 to 16")
                              : a == "none" ? (by_msaa ? "none is msaa: 0" : "none is samples: 1")
                                            : "fxaa draws one sample of its own: leave the count out";
      fail(v, k, a + " contradicts " + count + " (" + why + ")");
    }
    r.antialias = a;
  });
  optional(n, path, "color", [&](auto& v, auto& k) {
    const std::string c = string(v, k);
    if (!parse_field_kind(c)) fail(v, k, "unknown colouring " + in_quotes(c) + " (expected checker, error, strain or speed)");
    r.color = c;
  });
  optional(n, path, "overlay", [&](auto& v, auto& k) {
    const std::string o = string(v, k);
    if (o != "full" && o != "label" && o != "none") fail(v, k, "unknown overlay " + in_quotes(o) + " (expected full, label or none)");
    r.overlay = o;
  });
  optional(n, path, "camera", [&](auto& v, auto& k) {
    // `camera: auto` frames the cloth and spheres from the scene's own extent.
    // `camera: course` is the course framework's view, the defaults of CameraDef.
    if (v.IsScalar()) {
      if (v.Scalar() == "auto") r.camera_auto = true;
      else if (v.Scalar() == "course") r.camera = CameraDef{};
      else fail(v, k, "expected auto, course or a map of eye, target, up, fov, got " + in_quotes(v.Scalar()));
      return;
    }
    expect_map(v, k, {"eye", "target", "up", "fov"});
    optional(v, k, "eye", [&](auto& w, auto& kk) { r.camera.eye = vec3(w, kk); });
    optional(v, k, "target", [&](auto& w, auto& kk) { r.camera.target = vec3(w, kk); });
    optional(v, k, "up", [&](auto& w, auto& kk) { r.camera.up = vec3(w, kk); });
    optional(v, k, "fov", [&](auto& w, auto& kk) { r.camera.fov = in_range(w, kk, 1.0, 170.0); });
    if ((r.camera.eye - r.camera.target).norm() == 0.0) fail(v, k, "eye and target coincide");
  });
  return r;
}

ImplicitDef Reader::implicit(const YAML::Node& n, const std::string& path) const {
  ImplicitDef d;
  expect_map(n, path, {"solver", "newton_max_iterations", "newton_tolerance", "cg_max_iterations",
                       "cg_tolerance", "iterations", "preconditioner"});
  optional(n, path, "solver", [&](auto& v, auto& k) {
    const std::string s = string(v, k);
    if (s == "newton") d.solver = ImplicitSolver::Newton;
    else if (s == "fixed_point") d.solver = ImplicitSolver::FixedPoint;
    else fail(v, k, "unknown solver " + in_quotes(s) + " (expected newton or fixed_point)");
  });
  optional(n, path, "newton_max_iterations", [&](auto& v, auto& k) { d.newton_max_iterations = int_in_range(v, k, 1, 1000); });
  optional(n, path, "newton_tolerance", [&](auto& v, auto& k) { d.newton_tolerance = positive(v, k); });
  optional(n, path, "cg_max_iterations", [&](auto& v, auto& k) { d.cg_max_iterations = int_in_range(v, k, 1, 100000); });
  optional(n, path, "cg_tolerance", [&](auto& v, auto& k) { d.cg_tolerance = positive(v, k); });
  optional(n, path, "iterations", [&](auto& v, auto& k) { d.fixed_point_iterations = int_in_range(v, k, 1, 1000); });
  optional(n, path, "preconditioner", [&](auto& v, auto& k) {
    const std::string s = string(v, k);
    if (s == "auto") d.preconditioner = PreconditionerKind::Auto;
    else if (s == "block_jacobi") d.preconditioner = PreconditionerKind::BlockJacobi;
    else if (s == "cholesky") d.preconditioner = PreconditionerKind::Cholesky;
    else if (s == "multigrid") d.preconditioner = PreconditionerKind::Multigrid;
    else fail(v, k, "unknown preconditioner " + in_quotes(s) + " (expected auto, block_jacobi, cholesky or multigrid)");
  });
  return d;
}

// The iterative solvers' blocks: `xpbd: {iterations, tolerance}`, `projective_dynamics:
// {iterations, chebyshev_rho, tolerance}`, `vbd: {iterations, chebyshev_rho, tolerance}`
// (method_params.h holds the defaults).
void Reader::solvers(const YAML::Node& root, SolverDefs& d) const {
  const auto count = [&](const YAML::Node& v, const std::string& k) {
    return int_in_range(v, k, 1, kMaxSolverIterations);
  };
  const auto tolerance = [&](const YAML::Node& v, const std::string& k) { return in_range(v, k, 0.0, 0.5); };
  optional(root, "", "xpbd", [&](auto& n, auto& k) {
    expect_map(n, k, {"iterations", "tolerance"});
    optional(n, k, "iterations", [&](auto& v, auto& kk) { d.xpbd.iterations = count(v, kk); });
    optional(n, k, "tolerance", [&](auto& v, auto& kk) { d.xpbd.tolerance = tolerance(v, kk); });
  });
  optional(root, "", "projective_dynamics", [&](auto& n, auto& k) {
    expect_map(n, k, {"iterations", "chebyshev_rho", "tolerance"});
    optional(n, k, "iterations", [&](auto& v, auto& kk) { d.projective_dynamics.iterations = count(v, kk); });
    optional(n, k, "tolerance", [&](auto& v, auto& kk) { d.projective_dynamics.tolerance = tolerance(v, kk); });
    optional(n, k, "chebyshev_rho", [&](auto& v, auto& kk) {
      d.projective_dynamics.chebyshev_rho = in_range(v, kk, 0.0, 0.9999);
    });
  });
  optional(root, "", "vbd", [&](auto& n, auto& k) {
    expect_map(n, k, {"iterations", "chebyshev_rho", "tolerance"});
    optional(n, k, "iterations", [&](auto& v, auto& kk) { d.vbd.iterations = count(v, kk); });
    optional(n, k, "tolerance", [&](auto& v, auto& kk) { d.vbd.tolerance = tolerance(v, kk); });
    optional(n, k, "chebyshev_rho", [&](auto& v, auto& kk) { d.vbd.chebyshev_rho = in_range(v, kk, 0.0, 0.9999); });
  });
}

}  // namespace clothsim::scene_detail
