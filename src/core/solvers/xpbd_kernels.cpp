#include "xpbd_kernels.h"

namespace clothsim {

double solve_distance_constraint(Vec3& ya, Vec3& yb, const Vec3& xa, const Vec3& xb, double wa,
                                 double wb, double rest, double ks, double kd, double h,
                                 double lambda) {
  const Vec3 d = ya - yb;
  const double l = d.norm();
  const double w = wa + wb;
  if (l <= 0.0 || w == 0.0) return 0.0;
  const Vec3 u = d / l;
  const double compliance_scale = ks * h * h;  // alpha~^-1
  const double rate = u.dot((ya - xa) - (yb - xb));  // grad C . (y - x_n)
  const double dlambda = (-compliance_scale * (l - rest) - lambda - kd * h * rate) /
                         ((compliance_scale + kd * h) * w + 1.0);
  ya += (wa * dlambda) * u;
  yb -= (wb * dlambda) * u;
  return dlambda;
}

void solve_contact_constraint(Vec3& y, const Vec3& x_start, double h, const Penetration& c) {
  y += c.depth * c.normal;
  Vec3 slide = (y - x_start) - h * c.collider_velocity;
  slide -= c.normal * c.normal.dot(slide);
  const double length = slide.norm();
  const double bound = c.friction * c.depth;
  if (length <= 0.0 || bound <= 0.0) return;
  y -= length <= bound ? slide : Vec3((bound / length) * slide);
}

}  // namespace clothsim
