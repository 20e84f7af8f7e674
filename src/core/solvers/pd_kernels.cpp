#include "pd_kernels.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <iterator>

#include "contact_scan_kernels.h"
#include "pd_local_kernels.h"
#include "pd_solve_kernels.h"

namespace clothsim {
namespace {

// Supernodes may store zeros up to this share of their panels: the fastest solve at 64x64
// among 0, 0.15, 0.3 and 0.5 (BENCHMARKS.md, "The iterative solvers").
constexpr double kMaxZeroShare = 0.3;

void number_free_bodies(const Eigen::VectorXd& inv_mass, PdFactor& f) {
  f.free_index.assign(inv_mass.size(), -1);
  std::int32_t row = 0;
  for (Eigen::Index i = 0; i < inv_mass.size(); ++i)
    if (inv_mass[i] != 0.0) f.free_index[i] = row++;
}

// Each free body's row in the factor's order: Eigen's solve takes P b, row free_index -> P's index.
void number_factor_rows(PdFactor& f) {
  const auto& perm = f.ldlt.permutationP().indices();
  f.row.assign(f.free_index.size(), -1);
  for (std::size_t i = 0; i < f.free_index.size(); ++i)
    if (f.free_index[i] >= 0) f.row[i] = perm.size() > 0 ? perm[f.free_index[i]] : f.free_index[i];
}

Eigen::SparseMatrix<double> global_matrix(const Model& model, const StepProblem& p,
                                          const PdFactor& f) {
  std::vector<Eigen::Triplet<double>> t;
  int rows = 0;

  for (std::size_t i = 0; i < f.free_index.size(); ++i)
    if (f.free_index[i] >= 0) t.emplace_back(f.free_index[i], f.free_index[i], p.weight[i]), ++rows;
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const int ra = f.free_index[s.a[k]], rb = f.free_index[s.b[k]];
    const double w = p.stiffness[k];
    if (ra >= 0) t.emplace_back(ra, ra, w);
    if (rb >= 0) t.emplace_back(rb, rb, w);
    if (ra >= 0 && rb >= 0) t.emplace_back(ra, rb, -w), t.emplace_back(rb, ra, -w);
  }
  Eigen::SparseMatrix<double> A(rows, rows);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// The scalar local step: each spring's k (p_s - d_s), its projection less its span d_s =
// y_a - y_b (the residual's share of A y), added to its free ends' rows.
void scatter_spring_projections(const Model& model, const StepProblem& p, const PdFactor& f,
                                const Eigen::Matrix3Xd& y, Eigen::Matrix4Xd& z) {
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const int ra = f.row[s.a[k]], rb = f.row[s.b[k]];
    const Vec3 d = y.col(s.a[k]) - y.col(s.b[k]);
    const double l = d.norm();
    const Vec3 proj = l > 0.0 ? Vec3((p.rest[k] / l - 1.0) * d) : Vec3(Vec3::Zero());
    const double w = p.stiffness[k];
    if (ra >= 0) z.col(ra).head<3>() += w * proj;
    if (rb >= 0) z.col(rb).head<3>() -= w * proj;
  }
}

// Uzawa: each multiplier raised by the depth the solve left its particle below its plane,
// clamped at 0. A particle takes its plane when it first enters a collider's reach in the
// step; only particles inside a reach or already pushed can change.
void update_contact_forces(const Model& model, const StepProblem& p, const PdFactor& f,
                           const Eigen::Matrix3Xd& y, PdSystem& s, std::vector<double>& lambda) {
  particles_in_reach(p.colliders, y, static_cast<std::size_t>(model.num_particles), s.inside);
  s.visit.clear();
  std::set_union(s.inside.begin(), s.inside.end(), s.pushed.begin(), s.pushed.end(), std::back_inserter(s.visit));
  s.pushed.clear();
  for (const std::int32_t i : s.visit) {
    if (f.free_index[i] < 0) continue;
    if (!s.planed[i]) held_plane(p.colliders, p.start.col(i), y.col(i), s.normal[i], s.plane[i]), s.planed[i] = 1;
    lambda[i] = std::max(0.0, lambda[i] + p.weight[i] * (s.plane[i] - s.normal[i].dot(y.col(i))));
    if (lambda[i] > 0.0) s.pushed.push_back(i);
  }
}

}  // namespace

bool pd_prepare_factor(const Model& model, const StepProblem& p, const Eigen::VectorXd& inv_mass,
                       PdFactor& f) {
  const bool pins_changed = f.model != &model || f.inv_mass.size() != inv_mass.size() ||
                            f.inv_mass != inv_mass;
  if (!pins_changed && f.h == p.h) return false;
  if (pins_changed) {
    number_free_bodies(inv_mass, f);
    f.inv_mass = inv_mass;
    f.model = &model;
    f.analysed = false;
  }
  f.h = p.h;
  const Eigen::SparseMatrix<double> A = global_matrix(model, p, f);
  if (!f.analysed) f.ldlt.analyzePattern(A), f.analysed = true;  // the pattern is the pins'
  f.ldlt.factorize(A);
  const auto& L = f.ldlt.matrixL().nestedExpression();
  f.panels = supernodes_of_float(static_cast<std::size_t>(L.cols()), L.outerIndexPtr(), L.innerIndexPtr(), L.valuePtr(),
                           f.ldlt.vectorD().data(), kMaxZeroShare);
  number_factor_rows(f);
  ++f.factorizations;
  return true;
}

void pd_prepare_step(const Model& model, const StepProblem& p, const PdFactor& f, PdSystem& s) {
  s.z.setZero(4, f.ldlt.rows());
  s.dz.setZero(4, f.ldlt.rows());
  s.pushed.clear();
  s.planed.assign(model.num_particles, 0);
  s.normal.resize(model.num_particles);
  s.plane.resize(model.num_particles);
  if (model.spring_path() != SpringPath::Families) return;
  const Springs& sp = model.springs;
  const SpringLayout& layout = model.spring_layout;
  s.rest.assign(layout.num_slots + layout.slot_gap, 0.0);
  for (std::size_t k = 0; k < sp.size(); ++k) s.rest[layout.slot[k]] = p.rest[k];
}

void pd_iteration(const Model& model, const StepProblem& p, const PdFactor& f, Eigen::Matrix3Xd& y,
                  PdSystem& s, std::vector<double>& lambda) {
  // r = b(y) - (A + L) y: the inertial term a (yhat - y), then the springs' and contacts' shares.
  for (std::size_t i = 0; i < f.row.size(); ++i)
    if (f.row[i] >= 0) s.z.col(f.row[i]).head<3>() = p.weight[i] * (p.target.col(i) - y.col(i));
  if (model.spring_path() == SpringPath::Families)
    pd_family_projections(model.spring_layout, y, s.rest.data(), p.h, f.row.data(), s.z);
  else
    scatter_spring_projections(model, p, f, y, s.z);
  for (std::int32_t i : s.pushed) s.z.col(f.row[i]).head<3>() += lambda[i] * s.normal[i];
  s.dz = s.z.cast<float>();
  ldlt_solve_padded(f.panels, s.dz.data());
  for (std::size_t i = 0; i < f.row.size(); ++i)
    if (f.row[i] >= 0) y.col(i) += s.dz.col(f.row[i]).head<3>().cast<double>();
  if (!p.colliders.ground && p.colliders.centre.empty()) return;
  update_contact_forces(model, p, f, y, s, lambda);
}

double chebyshev_omega(int k, double rho, double previous) {
  if (k <= 1) return 1.0;
  if (k == 2) return 2.0 / (2.0 - rho * rho);
  return 4.0 / (4.0 - rho * rho * previous);
}

}  // namespace clothsim
