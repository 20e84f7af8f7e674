// A method's own parameters by the names a lane gives them (`newmark@1/60:beta=0.3:gamma=0.6`,
// `generalized_alpha@1/60:rho=0.5`): which method takes which is its registry row's
// `parameters`; here, where each lives in MethodDefs and the values it takes.
#pragma once

#include <string>
#include <string_view>

#include "core/base/method_params.h"

namespace clothsim {

// Why `value` is no value of parameter `key` (one line), or "" when it is one.
//   beta   newmark's, in (0, 1/2]           (0 would be explicit: no potential to minimise)
//   gamma  newmark's, in [1/2, 1]           (below 1/2 the scheme grows; above, it damps, first order)
//   rho    generalized_alpha's rho_inf, in [0, 1]
std::string method_param_problem(std::string_view key, double value);

// Sets parameter `key` (one method_param_problem accepts) in `methods`.
void set_method_param(MethodDefs& methods, std::string_view key, double value);

// Whether `kind`'s registry row lists `key` among its parameters.
bool takes_method_param(IntegratorKind kind, std::string_view key);

}  // namespace clothsim
