// SpringLayout: the model's springs regrouped for the SIMD force pass (spring_kernels.h).
//
// A cloth grid's springs come in families that repeat one stencil: structural (i, j) -> (i+1, j)
// and (i, j) -> (i, j+1), shear (i, j) -> (i+1, j+1) and (i+1, j) -> (i, j+1), bend (i, j) ->
// (i+2, j) and (i, j) -> (i, j+2). With particle p = j nx + i, every spring of a family joins
// its lower particle p to p + offset (offset 1, nx, nx+1, nx-1, 2 and 2 nx), so a family is fully
// described by its offset and, per position p, its rest length (or "no spring here", at the
// grid's edges). A kernel then reads the ends of L consecutive springs with two contiguous
// loads (p .. p+L-1 and p+offset .. p+offset+L-1) and no gathers, and accumulates their
// forces with contiguous adds, free of conflicts because the lanes of one load are distinct
// particles.
//
// The layout is recognised from the springs themselves, not from the scene: a spring joins a
// family when it is a grid stencil of the model's nx x ny grid, has a positive finite rest
// length and shares the family's stiffness and damping (the first spring seen sets them).
// Whatever does not fit (none from today's scenes) stays in `others`, for the scalar pass.
// Built once with the model (build_model) and never written afterwards.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "springs.h"
#include "core/base/step_context.h"  // SpringPath

namespace clothsim {

// The family's springs join a = first + k to a + offset, for k in [0, count) where rest[k] > 0.
struct SpringFamily {
  int di = 0, dj = 0;         // grid step from a to b: b = (i + di, j + dj)
  std::int32_t offset = 0;    // b - a = dj nx + di (particles)
  std::int32_t first = 0;     // particle index of the first position
  std::int32_t count = 0;     // positions first .. first + count - 1
  double ks = 0.0, kd = 0.0;  // N/m, N s/m: one value for the whole family
  // (count rounded up to kSpringLanePad) rest length l0 of the spring at a = first + k, m;
  // 0 where the family has no spring (grid edges, the padding).
  std::vector<double> rest;
  std::size_t springs = 0;    // how many positions hold a spring
  std::size_t slot_first = 0;  // where position 0 sits in the layout's slot order (below)
};

// Vector loads may run this many doubles past a family's last position and past the last
// particle; the layout pads its arrays (and the kernel its scratch) by as much. 16 covers
// every x86 target (8 doubles for AVX-512) with room.
inline constexpr int kSpringLanePad = 16;

struct SpringLayout {
  int num_particles = 0;                // P: particles the families index (the grid's nx ny)
  std::vector<SpringFamily> families;   // in order of first appearance in the springs
  Springs others;                       // springs in no family, in their model order
  std::size_t num_springs = 0;          // springs laid out (families + others)
  // Slot order, for per-spring arrays a SIMD pass reads by family position (the implicit
  // step's start lengths and Newton blocks): every family's padded positions in turn (family f
  // at slot_first .. slot_first + rest.size() - 1, zeros where it holds no spring), each after
  // slot_gap empty slots and the last followed by as many, then the others in their order from
  // others_first. Unused slots hold zeros. The gaps let a pass read a family's slots by
  // particle rather than by position (the springs whose a, or whose b, is p .. p+L-1, for any
  // vector of particles that meets the family): such a read starts at most L - 1 slots before
  // the family's first slot or ends as far past its last, in zeros either way (the assembly's
  // diagonal blocks, potential_kernels.h).
  std::vector<std::int32_t> slot;       // (num_springs) spring s's slot
  std::size_t slot_gap = 0;             // kSpringLanePad: empty slots before each family and after the last
  std::size_t others_first = 0;         // slot of others[0]
  std::size_t num_slots = 0;            // others_first + others.size()

  // True when the layout describes a springs array of this many springs and has families
  // to run (otherwise the scalar pass is all there is).
  bool covers(std::size_t total_springs) const {
    return num_springs == total_springs && !families.empty();
  }
};

// How every pass walks a model's springs, decided here and nowhere else: the scalar list when
// the layout does not describe these springs, the families alone when they hold every spring of
// a layout over the model's own particles, else both.
inline SpringPath spring_path(const SpringLayout& layout, std::size_t total_springs, int num_particles) {
  if (!layout.covers(total_springs)) return SpringPath::List;
  if (layout.others.size() == 0 && layout.num_particles == num_particles) return SpringPath::Families;
  return SpringPath::Mixed;
}

// The slot order a model's per-spring step arrays use: the layout's when it covers the springs,
// else spring order itself (a stale layout or no grid: the scalar passes only).
inline std::size_t slot_count(const SpringLayout& layout, std::size_t total_springs) {
  return layout.covers(total_springs) ? layout.num_slots : total_springs;
}

// Regroups `springs` over an nx x ny particle grid (p = j nx + i) into stencil families.
// nx or ny 0 (no grid): every spring goes to `others`.
SpringLayout build_spring_layout(const Springs& springs, int nx, int ny);

}  // namespace clothsim
