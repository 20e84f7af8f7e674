#include "integrators/sparse_system.h"

#include <Eigen/LU>  // Matrix3d::inverse (closed form for 3x3)

namespace clothsim {

void build_pattern(const Model& model, SpringBlockMatrix& A) {
  const int B = model.num_bodies();
  A.a = model.springs.a;
  A.b = model.springs.b;
  A.diag.assign(B, Mat3::Zero());
  A.diag_inverse.assign(B, Mat3::Identity());
  A.off.assign(model.springs.size(), Mat3::Zero());
}

void assemble_backward_euler_matrix(const Model& model, const Eigen::Matrix3Xd& x,
                                    const Eigen::Matrix3Xd& v, const Eigen::VectorXd& inv_mass,
                                    double h, bool clamp_compression, SpringBlockMatrix& A,
                                    Eigen::Matrix3Xd& Jv) {
  const int B = A.num_bodies();
  const Springs& springs = model.springs;
  Jv.setZero(3, B);

  // M, plus h c I for air drag (df/dv = -c I on cloth particles).
  for (int i = 0; i < B; ++i) {
    if (inv_mass[i] == 0.0) {
      A.diag[i].setIdentity();
      continue;
    }
    const double drag = i < model.num_particles ? model.air_drag : 0.0;
    A.diag[i] = (1.0 / inv_mass[i] + h * drag) * Mat3::Identity();
  }

  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int a = A.a[s], b = A.b[s];
    const bool move_a = inv_mass[a] != 0.0, move_b = inv_mass[b] != 0.0;
    if (!move_a && !move_b) {
      A.off[s].setZero();
      continue;
    }
    // The symmetric part of spring_force.h's Jacobians in closed form (no 3x3 products):
    // with P = u u^T and t = 1 - l0/l, the stiffness part of df_a/dx_a is
    // K = -ks [P + t (I - P)] = -ks [t I + (1 - t) P] and df_a/dv_a = -kd P, so
    // G = h df/dv + h^2 K = -(h^2 ks t) I - (h kd + h^2 ks (1 - t)) P.
    // Clamping compression (t < 0 -> 0) keeps only the axial stiffness -ks P.
    const Vec3 d = x.col(a) - x.col(b);
    const Vec3 vr = v.col(a) - v.col(b);
    const double l = d.norm();
    const double ks = springs.ks[s], kd = springs.kd[s];
    Mat3 G;
    Vec3 jv;  // (df_a/dx_a) (v_a - v_b): df_a/dx_b = -df_a/dx_a, so ((df/dx) v)_a is this
    if (l > 0.0) {
      const Vec3 u = d / l;
      const double t_exact = 1.0 - springs.rest[s] / l;
      const double t = clamp_compression && t_exact < 0.0 ? 0.0 : t_exact;
      const double iso = h * h * ks * t;
      const double axial = h * kd + h * h * ks * (1.0 - t);
      G.noalias() = -axial * (u * u.transpose());
      G.diagonal().array() -= iso;
      // Exact df_a/dx_a applied to vr: stiffness -ks [t I + (1 - t) P] vr, and the damper's
      // -(kd / l) [(vr.u) Q + u vr^T Q] vr with Q vr = vr - (u.vr) u, vr^T Q vr = |vr|^2 - (u.vr)^2.
      const double uv = u.dot(vr);
      jv = -ks * (t_exact * vr + (1.0 - t_exact) * uv * u) -
           (kd / l) * (uv * (vr - uv * u) + (vr.squaredNorm() - uv * uv) * u);
    } else {  // coincident ends: spring_damper_jacobian's isotropic stand-in
      G = -(h * kd / 3.0 + h * h * ks) * Mat3::Identity();
      jv = -ks * vr;
    }
    if (move_a) A.diag[a] -= G;
    if (move_b) A.diag[b] -= G;
    if (move_a && move_b) {
      A.off[s] = G;
    } else {
      A.off[s].setZero();  // a filtered body's row and column are removed
    }
    if (move_a) Jv.col(a) += jv;
    if (move_b) Jv.col(b) -= jv;
  }

  for (int i = 0; i < B; ++i) A.diag_inverse[i] = A.diag[i].inverse();
}

// The CG hot loop (one call per iteration): written on raw column-major arrays, as the
// force pass is, so each 3x3 block product stays in registers. Blocks are symmetric, so
// the spring block serves (a, b) and (b, a) alike.
void multiply(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y) {
  const int B = A.num_bodies();
  y.resize(3, B);
  const double* P = p.data();
  double* Y = y.data();
  for (int i = 0; i < B; ++i) {
    const double* D = A.diag[i].data();
    const double* pi = P + 3 * i;
    double* yi = Y + 3 * i;
    yi[0] = D[0] * pi[0] + D[3] * pi[1] + D[6] * pi[2];
    yi[1] = D[1] * pi[0] + D[4] * pi[1] + D[7] * pi[2];
    yi[2] = D[2] * pi[0] + D[5] * pi[1] + D[8] * pi[2];
  }
  const std::size_t S = A.off.size();
  const std::int32_t* ia = A.a.data();
  const std::int32_t* ib = A.b.data();
  for (std::size_t s = 0; s < S; ++s) {
    const double* G = A.off[s].data();
    const std::size_t a = 3 * static_cast<std::size_t>(ia[s]);
    const std::size_t b = 3 * static_cast<std::size_t>(ib[s]);
    const double pa0 = P[a], pa1 = P[a + 1], pa2 = P[a + 2];
    const double pb0 = P[b], pb1 = P[b + 1], pb2 = P[b + 2];
    Y[a] += G[0] * pb0 + G[3] * pb1 + G[6] * pb2;
    Y[a + 1] += G[1] * pb0 + G[4] * pb1 + G[7] * pb2;
    Y[a + 2] += G[2] * pb0 + G[5] * pb1 + G[8] * pb2;
    Y[b] += G[0] * pa0 + G[3] * pa1 + G[6] * pa2;
    Y[b + 1] += G[1] * pa0 + G[4] * pa1 + G[7] * pa2;
    Y[b + 2] += G[2] * pa0 + G[5] * pa1 + G[8] * pa2;
  }
}

}  // namespace clothsim
