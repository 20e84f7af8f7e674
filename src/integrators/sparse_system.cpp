#include "integrators/sparse_system.h"

#include <Eigen/LU>  // Matrix3d::inverse (closed form for 3x3)

namespace clothsim {

void build_pattern(const Model& model, SpringBlockMatrix& A) {
  const int B = model.num_bodies();
  const std::size_t S = model.springs.size();
  A.a = model.springs.a;
  A.b = model.springs.b;
  A.diag.assign(B, Mat3::Zero());
  A.off.assign(S, Mat3::Zero());
  A.diag_projected.assign(B, Mat3::Zero());
  A.off_projected.assign(S, Mat3::Zero());
  A.diag_inverse.assign(B, Mat3::Identity());
}

void assemble_step_hessian(const Model& model, const Eigen::VectorXd& inv_mass, double h,
                           const std::vector<double>& start_length, const Eigen::Matrix3Xd& y,
                           bool project, SpringBlockMatrix& A) {
  const int B = A.num_bodies();
  const Springs& springs = model.springs;

  // M, plus h c I for air drag (the drag term (h c / 2) |v|^2 of Phi).
  for (int i = 0; i < B; ++i) {
    if (inv_mass[i] == 0.0) {
      A.diag[i].setIdentity();
    } else {
      const double drag = i < model.num_particles ? model.air_drag : 0.0;
      A.diag[i] = (1.0 / inv_mass[i] + h * drag) * Mat3::Identity();
    }
    A.diag_projected[i] = A.diag[i];
  }

  const double h2 = h * h;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int a = A.a[s], b = A.b[s];
    const bool move_a = inv_mass[a] != 0.0, move_b = inv_mass[b] != 0.0;
    if (!move_a && !move_b) {
      A.off[s].setZero();
      A.off_projected[s].setZero();
      continue;
    }
    const StepSpringBlock k = step_spring_block(y.col(a) - y.col(b), springs.rest[s],
                                                start_length[s], springs.ks[s], springs.kd[s], h);
    // Projected and exact differ only across a spring in compression (transverse < 0).
    Mat3 G = -h2 * k.matrix();
    Mat3 G_projected = G;  // -h^2 (K - transverse (I - u u^T)) where transverse < 0
    if (k.transverse < 0.0)
      G_projected += (h2 * k.transverse) * (Mat3::Identity() - k.u * k.u.transpose());
    if (project) G = G_projected;
    if (move_a) {
      A.diag[a] -= G;
      A.diag_projected[a] -= G_projected;
    }
    if (move_b) {
      A.diag[b] -= G;
      A.diag_projected[b] -= G_projected;
    }
    if (move_a && move_b) {
      A.off[s] = G;
      A.off_projected[s] = G_projected;
    } else {  // a filtered body's row and column are removed
      A.off[s].setZero();
      A.off_projected[s].setZero();
    }
  }

  for (int i = 0; i < B; ++i) A.diag_inverse[i] = A.diag_projected[i].inverse();
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
