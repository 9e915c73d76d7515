// triangleBoxOverlap against hand-built cases (each separating axis family, touching
// contacts) and two independent oracles on random triangles and boxes:
//  - clipping: the triangle clipped by the box's six half-spaces (Sutherland-Hodgman) is
//    non-empty iff they overlap. Evaluated on a box shrunk and a box grown by 1e-9, so round-off
//    on near-touching cases cannot make the oracle wrong: overlap with the shrunk box =>
//    SAT must say overlap; no overlap with the grown box => SAT must say none.
//  - dense sampling: if any barycentric sample of the triangle lies in the box, SAT must say
//    overlap; if SAT says none, no sample may lie inside.
#include "sim/shape/voxelize.h"

#include <gtest/gtest.h>

#include <vector>

#include "sim/core/prng.h"

namespace vf {
namespace {

bool clipOverlap(const Vec3& c, const Vec3& h, const Vec3& a, const Vec3& b, const Vec3& d) {
  std::vector<Vec3> poly = {a, b, d};
  for (int k = 0; k < 3 && !poly.empty(); ++k) {
    for (double side : {1.0, -1.0}) {
      // Keep side * (x_k - c_k) <= h_k.
      auto dist = [&](const Vec3& p) { return side * (p[k] - c[k]) - h[k]; };
      std::vector<Vec3> out;
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const Vec3& p = poly[i];
        const Vec3& q = poly[(i + 1) % poly.size()];
        const double dp = dist(p), dq = dist(q);
        if (dp <= 0) out.push_back(p);
        if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
      }
      poly = std::move(out);
      if (poly.empty()) break;
    }
  }
  return !poly.empty();
}

bool sampledInside(const Vec3& c, const Vec3& h, const Vec3& a, const Vec3& b, const Vec3& d,
                   int n) {
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 p = a + (b - a) * (double(i) / n) + (d - a) * (double(j) / n);
      if (((p - c).cwiseAbs() - h).maxCoeff() <= 0) return true;
    }
  return false;
}

const Vec3 kC(0, 0, 0), kH(1, 1, 1);  // box [-1, 1]^3

TEST(TriangleBoxOverlap, HandCases) {
  // Fully inside, enclosing the box (large triangle through it), far away.
  EXPECT_TRUE(triangleBoxOverlap(kC, kH, Vec3(-.1, 0, 0), Vec3(.1, 0, 0), Vec3(0, .1, .1)));
  EXPECT_TRUE(triangleBoxOverlap(kC, kH, Vec3(-10, -10, 0), Vec3(10, -10, 0), Vec3(0, 20, 0)));
  EXPECT_FALSE(triangleBoxOverlap(kC, kH, Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(5, 6, 5)));
  // Box face axis: a triangle in the plane x = 1 touches; at x = 1 + 1e-9 it is separated.
  EXPECT_TRUE(triangleBoxOverlap(kC, kH, Vec3(1, -3, -3), Vec3(1, 3, -3), Vec3(1, 0, 3)));
  EXPECT_FALSE(triangleBoxOverlap(kC, kH, Vec3(1 + 1e-9, -3, -3), Vec3(1 + 1e-9, 3, -3),
                                  Vec3(1 + 1e-9, 0, 3)));
  // Triangle normal axis: a big triangle in the plane x+y+z = 3 touches the corner (1,1,1)
  // only; every coordinate range overlaps the box, so only the normal can separate it when
  // the plane moves out to x+y+z = 3 + 1e-6.
  for (double off : {0.0, 1e-6}) {
    const double s = 3 + off;
    const Vec3 a(s + 4, -2, -2), b(-2, s + 4, -2), c(-2, -2, s + 4);
    EXPECT_EQ(triangleBoxOverlap(kC, kH, a, b, c), off == 0) << off;
  }
  // Edge x edge axis: a triangle with one edge skew to the box edge x = y = 1 (along z).
  // With delta > 0 only the axis z x (1,-1,0) ~ (1,1,0) separates: the box axes overlap in
  // range and the triangle normal (24,24,-64) gives |48 + 48 delta| < 112.
  for (double delta : {-1e-6, 0.0, 1e-6}) {
    const Vec3 a(5 + delta, -3 + delta, 0), b(-3 + delta, 5 + delta, 0), c(5, 5, 3);
    EXPECT_EQ(triangleBoxOverlap(kC, kH, a, b, c), delta <= 0) << delta;
  }
  // Degenerate triangles: a segment piercing the box, a point on a corner, a point outside.
  EXPECT_TRUE(triangleBoxOverlap(kC, kH, Vec3(-5, 0.5, 0.5), Vec3(5, 0.5, 0.5), Vec3(5, 0.5, 0.5)));
  EXPECT_TRUE(triangleBoxOverlap(kC, kH, Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)));
  EXPECT_FALSE(triangleBoxOverlap(kC, kH, Vec3(1, 1, 1.01), Vec3(1, 1, 1.01), Vec3(1, 1, 1.01)));
  // Box not at the origin and not a cube.
  EXPECT_TRUE(triangleBoxOverlap(Vec3(10, 20, 30), Vec3(0.5, 1, 2), Vec3(10.5, 21, 32),
                                 Vec3(12, 21, 32), Vec3(12, 23, 32)));
  EXPECT_FALSE(triangleBoxOverlap(Vec3(10, 20, 30), Vec3(0.5, 1, 2), Vec3(10.6, 21, 32),
                                  Vec3(12, 21, 32), Vec3(12, 23, 32)));
}

TEST(TriangleBoxOverlap, MatchesClippingAndSamplingOnRandomCases) {
  Prng rng(2024);
  int overlaps = 0, separated = 0;
  for (int iter = 0; iter < 20000; ++iter) {
    const Vec3 c(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const Vec3 h(rng.uniform(0.05, 1), rng.uniform(0.05, 1), rng.uniform(0.05, 1));
    // Triangles of mixed size around the box: some tiny, some long slivers.
    const double size = iter % 3 == 0 ? 0.3 : 3.0;
    const Vec3 base(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    auto corner = [&] {
      return Vec3(base + size * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    };
    const Vec3 a = corner(), b = corner(), d = corner();
    const bool sat = triangleBoxOverlap(c, h, a, b, d);
    const Vec3 eps = Vec3::Constant(1e-9);
    if (clipOverlap(c, h - eps, a, b, d)) {
      EXPECT_TRUE(sat) << iter;
    }
    if (!clipOverlap(c, h + eps, a, b, d)) {
      EXPECT_FALSE(sat) << iter;
    }
    const bool sampled = sampledInside(c, h, a, b, d, 40);
    if (sampled) {
      EXPECT_TRUE(sat) << iter;
    }
    if (!sat) {
      EXPECT_FALSE(sampled) << iter;
    }
    (sat ? overlaps : separated)++;
  }
  // Both outcomes are well represented, so the comparison is not vacuous.
  EXPECT_GT(overlaps, 2000);
  EXPECT_GT(separated, 2000);
}

}  // namespace
}  // namespace vf
