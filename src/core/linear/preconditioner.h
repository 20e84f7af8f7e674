// What preconditioned CG (conjugate_gradient.h) asks of a preconditioner other than block
// Jacobi: z = M^-1 r with M symmetric positive definite, and whether M is built. The sparse
// factor (cholesky_preconditioner.h) and the V-cycle (multigrid_preconditioner.h) are two.
#pragma once

#include <Eigen/Core>

namespace clothsim {

class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual bool ready() const = 0;
  // z = M^-1 r, r and z (3 x B).
  virtual void apply(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) const = 0;
};

}  // namespace clothsim
