#include "pd_kernels.h"

#include <Eigen/SparseCore>
#include <algorithm>

namespace clothsim {
namespace {

void number_free_bodies(const Eigen::VectorXd& inv_mass, PdFactor& f) {
  f.free_index.assign(inv_mass.size(), -1);
  std::int32_t row = 0;
  for (Eigen::Index i = 0; i < inv_mass.size(); ++i)
    if (inv_mass[i] != 0.0) f.free_index[i] = row++;
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

// Adds each spring's projection k p_s (and a fixed end's position) to its free ends' rows.
void scatter_spring_projections(const Model& model, const StepProblem& p, const PdFactor& f,
                                const Eigen::Matrix3Xd& y, Eigen::MatrixX3d& rhs) {
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const int ra = f.free_index[s.a[k]], rb = f.free_index[s.b[k]];
    const Vec3 d = y.col(s.a[k]) - y.col(s.b[k]);
    const double l = d.norm();
    const Vec3 proj = l > 0.0 ? Vec3((p.rest[k] / l) * d) : Vec3(Vec3::Zero());
    const double w = p.stiffness[k];
    if (ra >= 0) rhs.row(ra) += (w * (rb >= 0 ? proj : Vec3(proj + y.col(s.b[k])))).transpose();
    if (rb >= 0) rhs.row(rb) -= (w * (ra >= 0 ? proj : Vec3(proj - y.col(s.a[k])))).transpose();
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
  ++f.factorizations;
  return true;
}

void pd_iteration(const Model& model, const StepProblem& p, const PdFactor& f, Eigen::Matrix3Xd& y,
                  Eigen::MatrixX3d& rhs, std::vector<double>& lambda) {
  rhs.setZero(f.ldlt.rows(), 3);
  for (std::size_t i = 0; i < f.free_index.size(); ++i)
    if (f.free_index[i] >= 0) rhs.row(f.free_index[i]) = p.weight[i] * p.target.col(i).transpose();
  for (std::size_t i = 0; i < lambda.size(); ++i)
    if (lambda[i] > 0.0)
      rhs.row(f.free_index[i]) += lambda[i] * deepest_penetration(p.colliders, y.col(i)).normal.transpose();
  scatter_spring_projections(model, p, f, y, rhs);
  const Eigen::MatrixX3d solved = f.ldlt.solve(rhs);
  for (std::size_t i = 0; i < f.free_index.size(); ++i)
    if (f.free_index[i] >= 0) y.col(i) = solved.row(f.free_index[i]).transpose();
  if (!p.colliders.ground && p.colliders.centre.empty()) return;
  for (int i = 0; i < model.num_particles; ++i) {
    if (f.free_index[i] < 0) continue;
    const Penetration c = deepest_penetration(p.colliders, y.col(i));
    if (c.depth > 0.0 || lambda[i] > 0.0) lambda[i] = std::max(0.0, lambda[i] + p.weight[i] * c.depth);
  }
}

double chebyshev_omega(int k, double rho, double previous) {
  if (k <= 1) return 1.0;
  if (k == 2) return 2.0 / (2.0 - rho * rho);
  return 4.0 / (4.0 - rho * rho * previous);
}

}  // namespace clothsim
