// The springs regrouped into grid-stencil families: every spring in exactly one place, and
// whatever is not a stencil of the grid left to the scalar pass.
#include "core/springs/spring_layout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include "test_support.h"

namespace clothsim {
namespace {

using testing::model_from_yaml;

Model sheet(int nx, int ny, const std::string& types = "structural: {}, shear: {}, bend: {}") {
  return model_from_yaml("cloth: {particles: [" + std::to_string(nx) + ", " + std::to_string(ny) +
                         "], springs: {" + types + "}}\n");
}

using SpringKey = std::tuple<int, int, double, double, double>;  // a, b, l0, ks, kd

std::vector<SpringKey> keys(const Springs& s) {
  std::vector<SpringKey> out;
  for (std::size_t i = 0; i < s.size(); ++i) out.emplace_back(s.a[i], s.b[i], s.rest[i], s.ks[i], s.kd[i]);
  return out;
}

// The springs the layout describes, families and others together, sorted.
std::vector<SpringKey> laid_out(const SpringLayout& L) {
  std::vector<SpringKey> out = keys(L.others);
  for (const SpringFamily& f : L.families) {
    std::size_t n = 0;
    for (int k = 0; k < f.count; ++k)
      if (f.rest[k] > 0.0) {
        out.emplace_back(f.first + k, f.first + k + f.offset, f.rest[k], f.ks, f.kd);
        ++n;
      }
    EXPECT_EQ(n, f.springs);
    EXPECT_EQ(f.rest.size() % kSpringLanePad, 0u);
    EXPECT_GE(f.rest.size(), static_cast<std::size_t>(f.count));
    EXPECT_TRUE(std::all_of(f.rest.begin() + f.count, f.rest.end(), [](double r) { return r == 0.0; }));
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(SpringLayout, EverySpringOfEverySheetIsInExactlyOneFamily) {
  for (const auto& [nx, ny] : std::vector<std::pair<int, int>>{{25, 25}, {7, 5}, {1, 9}, {9, 1}, {2, 2}, {3, 3}, {1, 1}}) {
    SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny));
    const Model m = sheet(nx, ny);
    const SpringLayout& L = m.spring_layout;
    std::vector<SpringKey> expected = keys(m.springs);
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(laid_out(L), expected);
    EXPECT_EQ(L.others.size(), 0u);  // build_springs makes only stencils
    EXPECT_EQ(L.num_springs, m.springs.size());
    EXPECT_EQ(L.num_particles, nx * ny);
  }
}

TEST(SpringLayout, FullSheetHasSixFamiliesWithTheirOffsets) {
  const Model m = sheet(7, 5);
  std::vector<std::tuple<int, int, int, std::size_t>> got;  // di, dj, offset, springs
  for (const SpringFamily& f : m.spring_layout.families) got.emplace_back(f.di, f.dj, f.offset, f.springs);
  const std::vector<std::tuple<int, int, int, std::size_t>> expected{
      {1, 0, 1, 6 * 5}, {0, 1, 7, 7 * 4},  {1, 1, 8, 6 * 4},  // structural, shear
      {-1, 1, 6, 6 * 4}, {2, 0, 2, 5 * 5}, {0, 2, 14, 7 * 3}};  // shear, bend
  EXPECT_EQ(got, expected);
  EXPECT_TRUE(m.spring_layout.covers(m.springs.size()));
}

TEST(SpringLayout, OnlyTheDeclaredTypesGetFamilies) {
  EXPECT_EQ(sheet(6, 6, "shear: {}").spring_layout.families.size(), 2u);
  EXPECT_EQ(sheet(6, 6, "bend: {}").spring_layout.families.size(), 2u);
  const Model none = sheet(6, 6, "");
  EXPECT_TRUE(none.spring_layout.families.empty());
  EXPECT_FALSE(none.spring_layout.covers(none.springs.size()));  // nothing for the kernel to do
}

TEST(SpringLayout, SpringsThatAreNotStencilsOrDifferInParametersGoToTheScalarPass) {
  Model m = sheet(4, 3, "structural: {stiffness: 100, damping: 2}");
  Springs s = m.springs;
  const auto add = [&](int a, int b, double l0, double ks, double kd) {
    s.a.push_back(a);
    s.b.push_back(b);
    s.rest.push_back(l0);
    s.ks.push_back(ks);
    s.kd.push_back(kd);
    s.type.push_back(SpringType::Structural);
  };
  add(0, 11, 1.0, 100, 2);  // across the sheet
  add(3, 4, 1.0, 100, 2);   // p -> p + 1 across a row's end: not (i + 1, j)
  add(0, 1, 1.0, 100, 2);   // a second spring where the family already has one
  add(5, 6, 1.0, 50, 2);    // a stencil with another stiffness
  add(1, 5, 0.0, 100, 2);   // zero rest length: the kernel's mask needs l0 > 0
  const SpringLayout L = build_spring_layout(s, 4, 3);
  EXPECT_EQ(L.others.size(), 5u);
  EXPECT_EQ(L.others.a, (std::vector<std::int32_t>{0, 3, 0, 5, 1}));
  std::vector<SpringKey> expected = keys(s);
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(laid_out(L), expected);
  EXPECT_TRUE(L.covers(s.size()));
  EXPECT_FALSE(L.covers(m.springs.size()));  // a layout of other springs is not used
}

TEST(SpringLayout, WithoutAGridEverySpringIsScalar) {
  const Model m = sheet(4, 3);
  const SpringLayout L = build_spring_layout(m.springs, 0, 0);
  EXPECT_TRUE(L.families.empty());
  EXPECT_EQ(L.others.size(), m.springs.size());
}

}  // namespace
}  // namespace clothsim
