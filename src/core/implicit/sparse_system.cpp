#include "sparse_system.h"

#include <utility>

#include "assembly_kernels.h"
#include "potential_kernels.h"
#include "core/linear/cg_kernels.h"

namespace clothsim {

void build_pattern(const Model& model, SpringBlockMatrix& A) { build_pattern(model, model.implicit.single_from, A); }

void build_pattern(const Model& model, int single_from, SpringBlockMatrix& A) {
  const int B = model.num_bodies();
  const std::size_t S = model.springs.size();
  const SpringLayout& layout = model.spring_layout;
  const bool families = model.spring_path() != SpringPath::List;
  const std::size_t slots = slot_count(layout, S);
  A.multiply = &multiply;
  const bool single = families && model.num_particles >= single_from;
  A.refresh_single_copy = single ? &refresh_single : nullptr;
  A.a = model.springs.a;
  A.b = model.springs.b;
  A.layout = families ? &layout : nullptr;
  A.slot.resize(S);
  for (std::size_t s = 0; s < S; ++s)
    A.slot[s] = families ? layout.slot[s] : static_cast<std::int32_t>(s);
  A.diag.assign(B, Mat3::Zero());
  for (auto* v : {&A.ux, &A.uy, &A.uz, &A.alpha, &A.beta, &A.alpha_projected, &A.beta_projected})
    v->assign(slots, 0.0);
  A.diag_projected.assign(B, Mat3::Zero());
  A.diag_inverse.assign(B, Mat3::Identity());
  A.refresh_copies();
  SpringBlockMatrix::to_soa(A.diag_inverse, A.diag_inverse_soa);
}

namespace {

// A body's diagonal block before the springs: M + h c I (air drag, the (h c / 2) |v|^2 term of
// Phi, on cloth particles; h the form's drag_h), or the identity for an immovable body (its row
// is filtered).
Mat3 mass_block(const Model& model, const Eigen::VectorXd& inv_mass, double h, int i) {
  if (inv_mass[i] == 0.0) return Mat3::Identity();
  const double drag = i < model.num_particles ? model.air_drag : 0.0;
  return (1.0 / inv_mass[i] + h * drag) * Mat3::Identity();
}

// A spring's block G = -h^2 K = alpha u u^T + beta I, alpha = -h^2 (axial - transverse),
// beta = -h^2 transverse, and its projection (transverse clamped at 0: positive semi-definite).
// With `project` the exact block is the projected one.
struct BlockCoefficients {
  double alpha, beta, alpha_projected, beta_projected;
};
BlockCoefficients block_coefficients(const StepSpringBlock& k, double h2, bool project) {
  const double transverse_projected = k.transverse < 0.0 ? 0.0 : k.transverse;
  BlockCoefficients c;
  c.alpha_projected = -h2 * (k.axial - transverse_projected);
  c.beta_projected = -h2 * transverse_projected;
  c.alpha = project ? c.alpha_projected : -h2 * (k.axial - k.transverse);
  c.beta = project ? c.beta_projected : -h2 * k.transverse;
  return c;
}

}  // namespace

void assemble_step_hessian_scalar(const Model& model, const Eigen::VectorXd& inv_mass, const StepForm& form,
                                  const std::vector<double>& start_length, const Eigen::Matrix3Xd& y,
                                  HessianBlocks blocks, SpringBlockMatrix& A, JacobiInverse jacobi) {
  const double h = form.h, damper_h = form.damper_h;
  const bool project = blocks == HessianBlocks::Projected;
  const int B = A.num_bodies();
  const Springs& springs = model.springs;

  for (int i = 0; i < B; ++i) A.diag[i] = mass_block(model, inv_mass, form.drag_h, i);

  // Each spring's block G (block_coefficients); the diagonal blocks get -G. The projected
  // diagonal is the exact one corrected for the compressed springs only (usually few), so the
  // common case pays for one diagonal accumulation.
  const double h2 = h * h;
  bool any_compressed = false;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int a = A.a[s], b = A.b[s];
    const std::size_t k_s = A.slot[s];
    const bool move_a = inv_mass[a] != 0.0, move_b = inv_mass[b] != 0.0;
    if (!move_a && !move_b) {
      A.alpha[k_s] = A.beta[k_s] = A.alpha_projected[k_s] = A.beta_projected[k_s] = 0.0;
      continue;
    }
    const StepSpringBlock k = step_spring_block(y.col(a) - y.col(b), springs.rest[s],
                                                start_length[k_s], springs.ks[s], springs.kd[s], damper_h);
    any_compressed |= k.transverse < 0.0;
    const BlockCoefficients c = block_coefficients(k, h2, project);
    if (move_a) subtract_block(A.diag[a], c.alpha, c.beta, k.u);
    if (move_b) subtract_block(A.diag[b], c.alpha, c.beta, k.u);
    A.ux[k_s] = k.u[0];
    A.uy[k_s] = k.u[1];
    A.uz[k_s] = k.u[2];
    if (move_a && move_b) {
      A.alpha[k_s] = c.alpha;
      A.beta[k_s] = c.beta;
      A.alpha_projected[k_s] = c.alpha_projected;
      A.beta_projected[k_s] = c.beta_projected;
    } else {  // a filtered body's row and column are removed
      A.alpha[k_s] = A.beta[k_s] = A.alpha_projected[k_s] = A.beta_projected[k_s] = 0.0;
    }
  }

  A.diag_projected = A.diag;
  if (any_compressed && !project) {
    for (std::size_t s = 0; s < springs.size(); ++s) {
      const int a = A.a[s], b = A.b[s];
      const bool move_a = inv_mass[a] != 0.0, move_b = inv_mass[b] != 0.0;
      if (!move_a && !move_b) continue;
      // Read back from the exact block (beta = -h^2 transverse) rather than recomputed or
      // stored twice: this pass runs only at iterates with compressed springs.
      const std::size_t k_s = A.slot[s];
      const double transverse = move_a && move_b ? -A.beta[k_s] / h2 : 0.0;
      double t = transverse;
      if (!(move_a && move_b)) {  // a filtered pair keeps no block: recompute its tension
        t = step_spring_block(y.col(a) - y.col(b), springs.rest[s], start_length[k_s],
                              springs.ks[s], springs.kd[s], damper_h).transverse;
      }
      if (t >= 0.0) continue;
      // Projected minus exact is h^2 t (I - u u^T), so the diagonal gets its negative.
      const double delta = h2 * t;
      if (move_a) subtract_block(A.diag_projected[a], -delta, delta, A.u(s));
      if (move_b) subtract_block(A.diag_projected[b], -delta, delta, A.u(s));
    }
  }

  A.refresh_copies();
  if (jacobi == JacobiInverse::Form) invert_diagonal(A);
}

void assemble_step_hessian(const Model& model, const Eigen::VectorXd& inv_mass, const StepForm& form,
                           const std::vector<double>& start_length, const Eigen::Matrix3Xd& y,
                           HessianBlocks blocks, SpringBlockMatrix& A, JacobiInverse jacobi) {
  const double h = form.h;
  if (!A.layout) {
    assemble_step_hessian_scalar(model, inv_mass, form, start_length, y, blocks, A, jacobi);
    return;
  }
  const bool project = blocks == HessianBlocks::Projected;
  const SpringLayout& layout = *A.layout;
  const int B = A.num_bodies();
  FamilyHessian out{A.ux.data(), A.uy.data(), A.uz.data(), A.alpha.data(), A.beta.data(),
                    A.alpha_projected.data(), A.beta_projected.data(), A.diag.data()->data(),
                    A.diag_projected.data()->data(), A.diag_soa.data()};
  out.bodies = static_cast<std::size_t>(B);
  out.h = h;
  out.damper_h = form.damper_h;
  out.drag_h = form.drag_h;
  out.drag = model.air_drag;
  out.project = project;
  // R needs no sum over the springs where nothing but the families' blocks is in D
  const bool rest_here = A.refresh_single_copy && layout.others.size() == 0;
  if (rest_here) {
    A.single.rest_soa.resize(6 * static_cast<std::size_t>(B));
    out.rest_soa = A.single.rest_soa.data();
  }
  // The families write the particles they reach; the rest (bodies past the grid, particles no
  // spring reaches) get M + h c I here, as the scalar assembly.
  const int written = static_cast<int>(family_assemble(layout, y, inv_mass, start_length.data(), out));
  for (int i = written; i < B; ++i) {
    A.diag[i] = mass_block(model, inv_mass, form.drag_h, i);
    if (!project) A.diag_projected[i] = A.diag[i];
  }

  // The others, one by one (none in today's scenes): their exact blocks into diag, their
  // projected ones into diag_projected.
  const double h2 = h * h;
  const Springs& others = layout.others;
  for (std::size_t j = 0; j < others.size(); ++j) {
    const int a = others.a[j], b = others.b[j];
    const std::size_t k_s = layout.others_first + j;
    const bool move_a = inv_mass[a] != 0.0, move_b = inv_mass[b] != 0.0;
    A.alpha[k_s] = A.beta[k_s] = A.alpha_projected[k_s] = A.beta_projected[k_s] = 0.0;
    if (!move_a && !move_b) continue;
    const StepSpringBlock k = step_spring_block(y.col(a) - y.col(b), others.rest[j],
                                                start_length[k_s], others.ks[j], others.kd[j], form.damper_h);
    const BlockCoefficients c = block_coefficients(k, h2, project);
    for (const int i : {a, b}) {
      if (inv_mass[i] == 0.0) continue;
      subtract_block(A.diag[i], c.alpha, c.beta, k.u);
      if (!project) subtract_block(A.diag_projected[i], c.alpha_projected, c.beta_projected, k.u);
    }
    A.ux[k_s] = k.u[0];
    A.uy[k_s] = k.u[1];
    A.uz[k_s] = k.u[2];
    if (move_a && move_b) {
      A.alpha[k_s] = c.alpha;
      A.beta[k_s] = c.beta;
      A.alpha_projected[k_s] = c.alpha_projected;
      A.beta_projected[k_s] = c.beta_projected;
    }
  }
  if (project) A.diag_projected = A.diag;
  // The bodies the families did not write, in diag_soa too (all of them if others changed
  // the particles' blocks).
  for (int i = others.size() == 0 ? written : 0; i < B; ++i) {
    const Mat3& D = A.diag[i];
    const double entry[6] = {D(0, 0), D(1, 1), D(2, 2), D(0, 1), D(0, 2), D(1, 2)};
    for (int e = 0; e < 6; ++e) A.diag_soa[e * B + i] = entry[e];
  }
  if (A.refresh_single_copy)
    A.refresh_single_copy(A, rest_here ? SpringBlockMatrix::Refresh::Springs : SpringBlockMatrix::Refresh::All);
  if (jacobi == JacobiInverse::Form) invert_diagonal(A);
}

void invert_diagonal(SpringBlockMatrix& A) {
  const std::size_t B = static_cast<std::size_t>(A.num_bodies());
  A.diag_inverse.resize(B);
  A.diag_inverse_soa.resize(6 * B);
  simd_invert_blocks(A.diag_projected.data()->data(), B, A.diag_inverse.data()->data(),
                     A.diag_inverse_soa.data());
}

namespace {

// y = the diagonal blocks times p (3 x B), for bodies from..B-1 (y sized 3 x B).
void multiply_diagonal(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y,
                       int from = 0) {
  const int B = A.num_bodies();
  y.resize(3, B);
  const double* P = p.data();
  double* Y = y.data();
  for (int i = from; i < B; ++i) {
    const double* D = A.diag[i].data();
    const double* pi = P + 3 * i;
    double* yi = Y + 3 * i;
    yi[0] = D[0] * pi[0] + D[3] * pi[1] + D[6] * pi[2];
    yi[1] = D[1] * pi[0] + D[4] * pi[1] + D[7] * pi[2];
    yi[2] = D[2] * pi[0] + D[5] * pi[1] + D[8] * pi[2];
  }
}

// y += the blocks of springs [0, n) (ends ia, ib; numbers at slot(s)) applied to p, on raw
// column-major arrays. A spring block applied to p is alpha u (u . p) + beta p, the same for
// (a, b) and (b, a).
template <class Slot>
void multiply_springs(const SpringBlockMatrix& A, std::size_t n, const std::int32_t* ia,
                      const std::int32_t* ib, const Slot& slot, const Eigen::Matrix3Xd& p,
                      Eigen::Matrix3Xd& y) {
  const double* P = p.data();
  double* Y = y.data();
  for (std::size_t s = 0; s < n; ++s) {
    const std::size_t k = slot(s);
    const double u[3] = {A.ux[k], A.uy[k], A.uz[k]};
    const std::size_t a = 3 * static_cast<std::size_t>(ia[s]);
    const std::size_t b = 3 * static_cast<std::size_t>(ib[s]);
    const double pa0 = P[a], pa1 = P[a + 1], pa2 = P[a + 2];
    const double pb0 = P[b], pb1 = P[b + 1], pb2 = P[b + 2];
    const double sa = A.alpha[k] * (u[0] * pa0 + u[1] * pa1 + u[2] * pa2);
    const double sb = A.alpha[k] * (u[0] * pb0 + u[1] * pb1 + u[2] * pb2);
    const double c = A.beta[k];
    Y[a] += sb * u[0] + c * pb0;
    Y[a + 1] += sb * u[1] + c * pb1;
    Y[a + 2] += sb * u[2] + c * pb2;
    Y[b] += sa * u[0] + c * pa0;
    Y[b + 1] += sa * u[1] + c * pa1;
    Y[b + 2] += sa * u[2] + c * pa2;
  }
}

}  // namespace

// The CG hot loop (one call per iteration).
void multiply(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y) {
  if (!A.layout) {
    multiply_scalar(A, p, y);
    return;
  }
  // The families' kernel writes y = D p + the families' blocks' terms for the particles it
  // reaches (the diagonal blocks from diag_soa, or A.single's float numbers where the matrix
  // keeps them); the rest of the bodies get D p here.
  const SpringLayout& layout = *A.layout;
  const int B = A.num_bodies();
  y.resize(3, B);
  const int written = static_cast<int>(
      A.refresh_single_copy
          ? family_multiply_single(layout,
                                   {A.single.ux.data(), A.single.uy.data(), A.single.uz.data(),
                                    A.single.alpha.data(), A.single.beta.data(), A.single.spring.data(),
                                    A.single.rest_soa.data(), static_cast<std::size_t>(B)},
                                   p, y)
          : family_multiply(layout,
                            {A.ux.data(), A.uy.data(), A.uz.data(), A.alpha.data(), A.beta.data(),
                             A.diag_soa.data(), static_cast<std::size_t>(B)},
                            p, y));
  multiply_diagonal(A, p, y, written);
  const std::size_t first = layout.others_first;
  multiply_springs(A, layout.others.size(), layout.others.a.data(), layout.others.b.data(),
                   [first](std::size_t s) { return first + s; }, p, y);
}

void refresh_single(SpringBlockMatrix& A, SpringBlockMatrix::Refresh what) {
  using Refresh = SpringBlockMatrix::Refresh;
  SpringBlockMatrix::Single& f = A.single;
  const SpringLayout& layout = *A.layout;
  if (what != Refresh::Rest) {
    for (auto [from, to] : {std::pair{&A.ux, &f.ux}, {&A.uy, &f.uy}, {&A.uz, &f.uz}, {&A.alpha, &f.alpha},
                            {&A.beta, &f.beta}}) {
      to->resize(from->size());
      demote_to_float(from->data(), from->size(), to->data());
    }
    if (f.spring.size() != layout.num_slots) {  // once per pattern
      f.spring.assign(layout.num_slots, 0);
      for (const SpringFamily& fam : layout.families)
        for (std::size_t k = 0; k < fam.rest.size(); ++k) f.spring[fam.slot_first + k] = fam.rest[k] > 0.0;
    }
  }
  const std::size_t B = static_cast<std::size_t>(A.num_bodies());
  f.rest_soa.resize(6 * B);
  if (what != Refresh::Springs) {
    family_rest_diagonal(*A.layout, A.ux.data(), A.uy.data(), A.uz.data(), A.alpha.data(), A.beta.data(),
                         A.diag_soa.data(), B, f.rest_soa.data());
    return;
  }
  // The assembly wrote R at the particles; the bodies past them keep D.
  for (std::size_t i = static_cast<std::size_t>(layout.num_particles); i < B; ++i)
    for (std::size_t e = 0; e < 6; ++e) f.rest_soa[e * B + i] = static_cast<float>(A.diag_soa[e * B + i]);
}

void multiply_scalar(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y) {
  multiply_diagonal(A, p, y);
  multiply_springs(A, A.num_springs(), A.a.data(), A.b.data(),
                   [&A](std::size_t s) { return static_cast<std::size_t>(A.slot[s]); }, p, y);
}

}  // namespace clothsim
