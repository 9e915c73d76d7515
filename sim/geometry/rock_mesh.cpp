// Rock meshes from (class, seed, size).
//
// EOTA blocks. The block of ETAG 027 / EAD 340059 drop tests, as inferred from the Chant Sura
// archive's shape files (/work/shared/rockfall-models.md section 9.5 gives the derivation): a
// cube of edge L with all 12 edges bevelled at 45 degrees by L/4, i.e. the convex hull of the
// 24 points whose coordinates are the permutations of (+-L/2, +-L/4, +-L/4). It has 26 faces
// (6 squares, 12 rectangles, 8 triangles), volume 17/24 L^3 and, about every axis through its
// centre, inertia 21/170 m L^2 (exact; docs/rockfall.md derives both). "eota_221" is the same
// solid stretched by (2, 2, 1): the platy block of the field tests.
//
// Natural rocks. Zingg's form classes (Zingg 1935) split rocks by two axis ratios of the long,
// intermediate and short axes a >= b >= c, each on either side of 2/3: b/a >= 2/3 and
// c/b >= 2/3 compact (Zingg's equant), c/b < 2/3 flat (disc, oblate), b/a < 2/3 elongated
// (rod, prolate), both < 2/3 bladed. A rock of a class is made in three steps from one seeded
// generator:
//   1. its ratios b/a and c/b, uniform over the class's range (below 2/3 the ranges stop at
//      1/3: thinner rocks are slabs that Zingg's classes do not single out, and whose voxel
//      trees need a finer level);
//   2. kPoints points uniform on the unit sphere (rejection from the cube, then normalised),
//      and their convex hull: a random convex polyhedron with angular faces and edges;
//   3. the hull stretched along x, y and z so that its extents are (a, b, c): from `extents`
//      as given, or from the ratios with a = `length`, or with the scale that gives `volume`.
// Stretching is linear, so step 3 keeps the hull convex and the ratios and volume exact to
// rounding. The generator draws the same numbers whatever the size, so one seed is one
// polyhedron at every size.
#include "sim/geometry/rock_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/prng.h"
#include "sim/geometry/convex_hull.h"
#include "sim/geometry/mass_properties.h"

namespace vf {
namespace {

// Points on the sphere per natural rock: a hull of n random points has 2n - 4 triangles, here
// 44, as many as the EOTA block's; enough facets for an angular silhouette at any level.
constexpr int kPoints = 24;
// Zingg's class boundary for b/a and c/b.
constexpr double kZingg = 2.0 / 3.0;
// Lowest ratio a natural rock is drawn with (see step 1).
constexpr double kLowestRatio = 1.0 / 3.0;

struct RockClass {
  const char* name;
  const char* zinggName;  // Zingg's name of the form class, for messages
  bool eota;
  Vec3 eotaStretch;  // eota: the 111 block's stretch
  // natural: ranges of b/a and c/b
  double elongationLo, elongationHi, flatnessLo, flatnessHi;
};

const std::vector<RockClass>& rockClasses() {
  static const std::vector<RockClass> classes = {
      {"eota_111", "", true, Vec3(1, 1, 1), 0, 0, 0, 0},
      {"eota_221", "", true, Vec3(2, 2, 1), 0, 0, 0, 0},
      {"compact", "equant", false, Vec3::Ones(), kZingg, 1, kZingg, 1},
      {"flat", "disc (oblate)", false, Vec3::Ones(), kZingg, 1, kLowestRatio, kZingg},
      {"elongated", "rod (prolate)", false, Vec3::Ones(), kLowestRatio, kZingg, kZingg, 1},
      {"bladed", "blade", false, Vec3::Ones(), kLowestRatio, kZingg, kLowestRatio, kZingg},
  };
  return classes;
}

const RockClass& rockClass(const std::string& name) {
  for (const RockClass& c : rockClasses())
    if (name == c.name) return c;
  VF_ASSERT(false && "unknown rock class; the scene loader checks names");
  return rockClasses().front();
}

// The 24 vertices of the EOTA 111 block of edge 1 (section comment at the top).
std::vector<Vec3> eotaPoints() {
  std::vector<Vec3> points;
  for (int axis = 0; axis < 3; ++axis)  // the coordinate that is +-1/2
    for (int s = 0; s < 8; ++s) {
      Vec3 p;
      p[axis] = s & 1 ? 0.5 : -0.5;
      p[(axis + 1) % 3] = s & 2 ? 0.25 : -0.25;
      p[(axis + 2) % 3] = s & 4 ? 0.25 : -0.25;
      points.push_back(p);
    }
  return points;
}

// Step 2: uniform on the unit sphere. The rejection keeps points away from the centre, where
// normalising would magnify rounding.
std::vector<Vec3> spherePoints(Prng& rng) {
  std::vector<Vec3> points;
  while (static_cast<int>(points.size()) < kPoints) {
    const Vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const double r2 = p.squaredNorm();
    if (r2 > 1e-2 && r2 <= 1) points.push_back(p / std::sqrt(r2));
  }
  return points;
}

// Moves the bounding box's centre to the origin and stretches the mesh so that its extents
// along x, y and z are `target`.
void fitExtents(TriMesh& mesh, const Vec3& target) {
  const Eigen::AlignedBox3d box = mesh.bounds();
  const Vec3 centre = box.center();
  const Vec3 factor = target.cwiseQuotient(box.sizes());
  for (Vec3& v : mesh.vertices) v = (v - centre).cwiseProduct(factor);
}

}  // namespace

const std::vector<std::string>& rockClassNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const RockClass& c : rockClasses()) out.push_back(c.name);
    return out;
  }();
  return names;
}

bool isRockClass(const std::string& name) {
  const auto& names = rockClassNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string rockExtentsProblem(const std::string& shapeClass, const Vec3& extents) {
  const RockClass& c = rockClass(shapeClass);
  if (c.eota) return "";
  std::array<double, 3> s{extents.x(), extents.y(), extents.z()};
  std::sort(s.begin(), s.end(), [](double p, double q) { return p > q; });
  const double elongation = s[1] / s[0], flatness = s[2] / s[1];
  const bool longSide = c.elongationLo >= kZingg, thickSide = c.flatnessLo >= kZingg;
  if ((elongation >= kZingg) == longSide && (flatness >= kZingg) == thickSide) return "";
  const RockClass* actual = nullptr;
  for (const RockClass& k : rockClasses())
    if (!k.eota && (elongation >= kZingg) == (k.elongationLo >= kZingg) &&
        (flatness >= kZingg) == (k.flatnessLo >= kZingg))
      actual = &k;
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "extents with b/a = %.3g and c/b = %.3g are Zingg's %s, class '%s', not '%s' "
                "(%s: b/a %s 2/3, c/b %s 2/3)",
                elongation, flatness, actual->zinggName, actual->name, c.name, c.name,
                longSide ? ">=" : "<", thickSide ? ">=" : "<");
  return buf;
}

double portableCubeRoot(double x) {
  VF_ASSERT(x > 0 && std::isfinite(x));
  int e = 0;
  double m = std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1): exact
  while (e % 3 != 0) {           // make e a multiple of 3, m in [0.5, 4): exact
    m *= 2;
    --e;
  }
  double y = 1.0;  // cbrt(m) lies in [0.79, 1.59]: Newton converges from 1 in a few steps;
  for (int i = 0; i < 10; ++i) y -= (y * y * y - m) / (3 * y * y);  // a fixed count, same bits
  return std::ldexp(y, e / 3);
}

TriMesh makeRockMesh(const RockDef& def) {
  const RockClass& c = rockClass(def.shapeClass);
  Prng rng(def.seed);
  // Step 1, drawn for every class and size so that the points below are always the same.
  const double elongation = rng.uniform(c.elongationLo, c.elongationHi);
  const double flatness = rng.uniform(c.flatnessLo, c.flatnessHi);
  TriMesh mesh;
  Vec3 relative;  // the extents for a longest extent of 1
  if (c.eota) {
    std::vector<Vec3> points = eotaPoints();
    for (Vec3& p : points) p = p.cwiseProduct(c.eotaStretch);
    mesh = convexHull(points);
    relative = c.eotaStretch / c.eotaStretch.maxCoeff();
  } else {
    mesh = convexHull(spherePoints(rng));
    relative = Vec3(1, elongation, elongation * flatness);
  }

  Vec3 target = relative;
  if (def.extents != Vec3::Zero()) {
    target = def.extents;
  } else if (def.length > 0) {
    target = def.length * relative;
  } else {
    VF_ASSERT(def.volume > 0);
    fitExtents(mesh, relative);
    target = portableCubeRoot(def.volume / computeMassProperties(mesh, 1.0).volume) * relative;
  }
  fitExtents(mesh, target);
  return mesh;
}

}  // namespace vf
