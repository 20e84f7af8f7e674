#include "spring_layout.h"

#include <algorithm>
#include <cmath>

namespace clothsim {
namespace {

void append(Springs& to, const Springs& from, std::size_t s) {
  to.a.push_back(from.a[s]);
  to.b.push_back(from.b[s]);
  to.rest.push_back(from.rest[s]);
  to.ks.push_back(from.ks[s]);
  to.kd.push_back(from.kd[s]);
  to.type.push_back(from.type[s]);
}

// The six stencils build_springs() makes (model.cpp); anything else is not a family here.
bool is_stencil(int di, int dj) {
  return (dj == 0 && (di == 1 || di == 2)) || (di == 0 && (dj == 1 || dj == 2)) ||
         (dj == 1 && (di == 1 || di == -1));
}

}  // namespace

SpringLayout build_spring_layout(const Springs& springs, int nx, int ny) {
  SpringLayout out;
  const std::size_t n = springs.size();
  out.num_springs = n;
  const bool grid = nx > 0 && ny > 0;
  out.num_particles = grid ? nx * ny : 0;
  const std::int32_t P = out.num_particles;

  // Pass 1: which family (index into out.families) each spring joins, or -1.
  std::vector<int> family_of(n, -1);
  std::vector<std::vector<std::uint8_t>> taken;  // (families x P) a position already holds a spring
  for (std::size_t s = 0; s < n && grid; ++s) {
    const std::int32_t a = springs.a[s], b = springs.b[s];
    const double l0 = springs.rest[s];
    if (a < 0 || b <= a || b >= P || !(l0 > 0.0) || !std::isfinite(l0)) continue;
    const int di = b % nx - a % nx, dj = b / nx - a / nx;
    if (!is_stencil(di, dj)) continue;
    int f = 0;
    while (f < static_cast<int>(out.families.size()) &&
           (out.families[f].di != di || out.families[f].dj != dj))
      ++f;
    if (f == static_cast<int>(out.families.size())) {
      SpringFamily fam;
      fam.di = di;
      fam.dj = dj;
      fam.offset = b - a;
      fam.ks = springs.ks[s];
      fam.kd = springs.kd[s];
      fam.first = a;
      out.families.push_back(fam);
      taken.emplace_back(P, 0);
    }
    SpringFamily& fam = out.families[f];
    // Bitwise-equal parameters only: the kernel broadcasts one ks and one kd per family.
    if (springs.ks[s] != fam.ks || springs.kd[s] != fam.kd || taken[f][a]) continue;
    taken[f][a] = 1;
    family_of[s] = f;
    fam.first = std::min(fam.first, a);
    fam.count = std::max(fam.count, a + 1);  // for now: one past the last position
    ++fam.springs;
  }

  // Pass 2: rest lengths by position, padded; the rest to the scalar pass. Slots: the
  // families' padded positions (each a multiple of kSpringLanePad), each after a gap of
  // slot_gap empty slots, a last gap, then the others.
  out.slot_gap = out.families.empty() ? 0 : kSpringLanePad;
  std::size_t slots = 0;
  for (SpringFamily& fam : out.families) {
    fam.count -= fam.first;
    const std::size_t padded =
        (static_cast<std::size_t>(fam.count) + kSpringLanePad - 1) / kSpringLanePad * kSpringLanePad;
    fam.rest.assign(padded, 0.0);
    fam.slot_first = slots + out.slot_gap;
    slots = fam.slot_first + padded;
  }
  slots += out.slot_gap;
  out.others_first = slots;
  out.slot.resize(n);
  for (std::size_t s = 0; s < n; ++s) {
    if (family_of[s] < 0) {
      out.slot[s] = static_cast<std::int32_t>(slots + out.others.size());
      append(out.others, springs, s);
      continue;
    }
    SpringFamily& fam = out.families[family_of[s]];
    fam.rest[springs.a[s] - fam.first] = springs.rest[s];
    out.slot[s] = static_cast<std::int32_t>(fam.slot_first + (springs.a[s] - fam.first));
  }
  out.num_slots = slots + out.others.size();
  return out;
}

}  // namespace clothsim
