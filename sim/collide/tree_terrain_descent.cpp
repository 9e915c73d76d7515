// Sphere tree against the terrain (a heightfield): fig. 3's descent of one tree against the
// surface, with the border wall.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/collide/descent_common.h"
#include "sim/geometry/mesh_bvh.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {
namespace {

// A node of a sphere tree met by descendAlone and the terrain descent.
struct NodeRef {
  int level;
  std::uint32_t index;
  Vec3 center;  // world
};

// Descends body a's sphere tree alone against something that is not a tree (the floor plane,
// the terrain), as fig. 3 does for two trees: the bounding sphere first, then level 1, then the
// children of every node that may touch. `mayTouch(centre, radius, bound)` may answer yes
// wrongly but never no wrongly (so no colliding leaf is missed); `bound` comes in as what the
// parent node's test left there (+infinity for the bounding sphere and level 1, whose spheres
// need not lie inside it) and may be updated for the node's children, whose spheres lie inside
// the node's. `leaf(node, radius)` emits the contact of a leaf sphere that passed, if it really
// collides. Returns the sphere tests made.
template <class MayTouch, class Leaf>
std::uint64_t descendAlone(const Collider& a, MayTouch mayTouch, Leaf leaf) {
  const SphereTree& tree = *a.tree;
  std::uint64_t tests = 1;
  double rootBound = INFINITY;
  if (!mayTouch(a.x, tree.boundingRadius, rootBound)) return tests;
  // The level-0 voxel is skipped: the bounding sphere above stands in for it.
  auto visit = [&](auto& self, const NodeRef& n, double bound) -> void {
    const SphereTreeLevel& lv = tree.levels[n.level];
    if (n.level == tree.leafLevel()) {
      leaf(n, lv.radius);
      return;
    }
    const SphereTreeLevel& next = tree.levels[n.level + 1];
    for (std::uint32_t i = lv.childBegin[n.index]; i < lv.childBegin[n.index + 1]; ++i) {
      const NodeRef child{n.level + 1, i, a.x + a.R * next.centers[i]};
      ++tests;
      double childBound = bound;
      if (mayTouch(child.center, next.radius, childBound)) self(self, child, childBound);
    }
  };
  visit(visit, NodeRef{0, 0, a.x}, INFINITY);
  return tests;
}

Contact groundContact(const Collider& a, const Collider& ground, const NodeRef& n) {
  Contact c;
  c.a = a.body;
  c.b = ground.body;
  c.leafA = n.index;
  c.leafB = kTerrainLeaf;  // used for the terrain only; the plane's contacts keep leafB = 0
  return c;
}

// The surface point nearest to c, closer than r, among the triangles of the cells within r of c:
// whether there is one, and if so the point and its squared distance.
bool nearestSurfacePoint(const Heightfield& field, const Vec3& c, double r, Vec3& nearest,
                         double& best) {
  int i0, i1, j0, j1;
  field.cellRange(c.x(), c.y(), r, i0, i1, j0, j1);
  best = r * r;
  bool found = false;
  Vec3 tri[2][3];
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      if (!field.hasCell(i, j)) continue;
      field.cellTriangles(i, j, tri);
      for (const auto& tr : tri) {
        // The triangle lies in its plane, so it holds no point nearer than the plane: a
        // triangle whose plane is farther than sqrt(best) is skipped (4 of 5 with 1,000
        // rocks, whose leaf tests mostly find nothing). The comparison allows a relative
        // 1e-9 for rounding, so it never skips a triangle that would have won: the same
        // nearest point, bit for bit.
        const Vec3 normal = (tr[1] - tr[0]).cross(tr[2] - tr[0]);
        const double s = normal.dot(c - tr[0]);
        if (s * s > best * normal.squaredNorm() * (1 + 1e-9)) continue;
        const Vec3 q = closestPointOnTriangle(c, tr[0], tr[1], tr[2]);
        const double d2 = (c - q).squaredNorm();
        if (d2 < best) best = d2, nearest = q, found = true;
      }
    }
  return found;
}

// The leaf test: the contact of leaf sphere n (radius r) of a with terrain t, appended to out if
// the sphere collides (see collideTreeHeightfield). xEnd, yEnd: the grid's far borders.
void terrainLeaf(const Collider& a, const Collider& t, double xEnd, double yEnd, const NodeRef& n,
                 double r, std::vector<Contact>& out) {
  const Heightfield& field = *t.terrain;
  const Vec3& c = n.center;
  Contact k = groundContact(a, t, n);
  const double h = field.heightAt(c.x(), c.y());
  if (!std::isnan(h) && c.z() < h) {  // centre inside the terrain
    k.normal = field.normalAt(c.x(), c.y());
    k.point = Vec3(c.x(), c.y(), h);
    k.depth = r + (h - c.z()) * k.normal.z();
    out.push_back(k);
    return;
  }
  const Vec3 border(std::clamp(c.x(), field.x0, xEnd), std::clamp(c.y(), field.y0, yEnd), c.z());
  if (border.x() != c.x() || border.y() != c.y()) {  // centre outside the grid
    const double hb = field.heightAt(border.x(), border.y());
    const double d = (c - border).norm();  // horizontal: same z
    if (!std::isnan(hb) && c.z() < hb) {   // beside the wall, below its top
      if (d < r) {
        k.normal = (c - border) / d;
        k.point = border;
        k.depth = r - d;
        out.push_back(k);
      }
      return;  // the wall is nearer than the surface above it
    }
  }
  Vec3 nearest;
  double best;
  if (!nearestSurfacePoint(field, c, r, nearest, best)) return;
  const double d = std::sqrt(best);
  if (d == 0.0) return;  // centre exactly on the surface: no defined normal (measure zero)
  k.normal = (c - nearest) / d;
  k.point = nearest;
  k.depth = r - d;
  out.push_back(k);
}

}  // namespace

// Sphere tree against terrain. A node may touch unless its sphere lies entirely above the
// highest sample under its footprint (a child's sphere lies in its parent's, so this never
// drops a node with colliding leaves). A leaf sphere collides if its centre is below the
// surface or the nearest surface triangle is closer than its radius; its contact point is that
// nearest surface point, its normal points from there to the centre (the surface normal when
// the centre is below the surface).
//
// The terrain is solid below its surface, so where the grid ends its border is a vertical wall
// from the border's surface line down (the paper has no terrain edges; voxfall's decision). A
// leaf sphere whose centre lies outside the grid, lower than the surface at the nearest border
// point, and closer to that point than its radius touches the wall there, with a horizontal
// normal. Without the wall, a rock that leaves a raised grid onto the floor plane of the paper's
// cliff scene (or is pushed off it by a pile) meets no terrain at the border and slides under the
// surface: 2-9 m deep by the true-mesh check, until the rock monitor buries it.
//
// Temporal coherence (PairCandidates; the terrain does not move, so the pair's pose is the
// body's). Why a margin bounds what a motion can change, although the leaf test is not
// Lipschitz in the centre (near a NODATA hole a centre deep below a cell is far from every
// triangle): the argument is containment, as for the plain descent. A node is dropped when its
// sphere S lies above `surfaceBoundNear` over S's footprint square, is clear of its planes, or
// lies above the surface by `sphereAbove`, and every way a sphere s inside S could touch (its
// centre below the surface, a triangle point inside it, the border wall beside it) needs a
// surface or wall point inside S or under that bound inside the square: none. A
// leaf that the descent widened by the margin m did not reach had such an S, of radius at least
// its own plus m, about its old centre; while no leaf centre has moved by m since, the leaf's
// sphere still lies inside S, so it does not touch. Every touching leaf is then a candidate,
// and the candidates are tested in the descent's order by the leaf test itself: the same
// contacts, bit for bit. The inner tests are widened by the rounding slack, as the plane's are.
std::uint64_t collideTreeHeightfield(const Collider& a, const Collider& t,
                                     std::vector<Contact>& out, PairCandidates* memo) {
  const Heightfield& field = *t.terrain;
  const SphereTree& tree = *a.tree;
  const double xEnd = field.x0 + (field.nx - 1) * field.cell;
  const double yEnd = field.y0 + (field.ny - 1) * field.cell;
  const double slack = roundingSlack(a.x, tree.boundingRadius);
  double widen = slack;  // added to every inner radius: the slack, and while building the margin
  // A child's sphere lies in its parent's, so the cells under it are some of the parent's and
  // the highest sample under it is no higher than the parent's: a child whose sphere lies above
  // that is dropped without looking the cells up (the same answer, cheaper; with 1,000 rocks the
  // lookups are otherwise a third of the terrain narrow phase's time).
  // An inner node that passes the bound and the planes gets the exact test, sphereAbove (a
  // leaf's own test is exact already). Near a ridge the planes keep nodes however far they are
  // from the surface (the other triangle's extended plane rises above it): a rock bouncing
  // down the Tyrol DEM's 5 m cells takes 83 leaf tests a step without it, for 0.06 contacts; 2.9
  // with it.
  const double leafRadius = tree.leaves().radius;
  auto mayTouch = [&](const Vec3& c, double r, double& bound) {
    const bool inner = r > leafRadius;
    r += widen;
    if (c.z() - r >= bound) return false;
    bool clear;
    bound = field.surfaceBoundNear(c, r, clear);
    if (clear || c.z() - r >= bound) return false;
    return !inner || !field.sphereAbove(c, r);
  };
  auto leaf = [&](const NodeRef& n, double r) { terrainLeaf(a, t, xEnd, yEnd, n, r, out); };
  if (!memo) return descendAlone(a, mayTouch, leaf);

  const int leafLevel = tree.leafLevel();
  // How far any leaf centre (within the bounding radius of the origin) moved since a pose.
  auto moved = [&](const Mat3& R, const Vec3& x) {
    return (a.x - x).norm() + (a.R - R).norm() * tree.boundingRadius;
  };
  const double margin = kCandidateMargin * leafRadius;
  const CandidatePlan plan = chooseCandidatePlan(
      *memo, memo->holds ? moved(memo->buildR, memo->buildT) : INFINITY,
      memo->hasLast ? moved(memo->lastR, memo->lastT) : INFINITY, margin, slack);
  memo->served = plan == CandidatePlan::kServe;
  if (memo->served) {
    std::uint64_t tests = 0;
    for (std::uint32_t i : memo->leaves) {
      ++tests;
      leaf(NodeRef{leafLevel, i, leafWorldCenter(a, i)}, leafRadius);
    }
    return tests;
  }
  memo->hasLast = true;
  memo->lastR = a.R;
  memo->lastT = a.x;
  memo->holds = plan == CandidatePlan::kBuild;
  if (!memo->holds) return descendAlone(a, mayTouch, leaf);
  memo->buildR = a.R;
  memo->buildT = a.x;
  memo->margin = margin;
  memo->leaves.clear();
  widen = slack + margin;
  // Every leaf the widened descent reaches is a candidate.
  return descendAlone(a, mayTouch, [&](const NodeRef& n, double r) {
    memo->leaves.push_back(n.index);
    leaf(n, r);
  });
}

std::uint64_t collideTreeHeightfield(const Collider& a, const Collider& t,
                                     std::vector<Contact>& out) {
  return collideTreeHeightfield(a, t, out, nullptr);
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TriangleFeature feature;
  return closestPointOnTriangle(p, a, b, c, feature);
}

}  // namespace vf
