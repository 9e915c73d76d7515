// What the narrow phase's sphere-tree descents share: the temporal-coherence plan, the leaf
// and plane expressions every test of a leaf must agree on to the bit, and the descents'
// entry points for the dispatch table and findContacts (narrow_phase.cpp). Private to
// sim/collide: included only by narrow_phase.cpp and the descent files (tree_tree_descent.cpp,
// tree_plane_descent.cpp, served_plane_patch.cpp, tree_terrain_descent.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/collide/narrow_phase.h"

namespace vf {

class PlanePatch;

// Temporal coherence (PairCandidates): candidates are kept within kCandidateMargin of the two
// leaf radii beyond touching, and built only after a step in which the pair moved less than
// kCalmStep of that margin, so that they are likely to serve several steps (a tumbling pair
// would rebuild them every step, at more than a plain descent's cost).
constexpr double kCandidateMargin = 0.25;
constexpr double kCalmStep = 0.25;

// What a pair's test does this time (PairCandidates): test only the stored candidates, build new
// ones while descending, or descend plainly. `sinceBuild` and `sinceLast` bound how far any leaf
// centre moved relative to the other side since the candidates' pose and since the last test's
// (infinity where there is none); `slack` is the pair's rounding slack.
enum class CandidatePlan { kServe, kBuild, kDescend };
inline CandidatePlan chooseCandidatePlan(const PairCandidates& m, double sinceBuild,
                                         double sinceLast, double margin, double slack) {
  if (m.holds && sinceBuild < m.margin - 2 * slack) return CandidatePlan::kServe;
  return sinceLast < kCalmStep * margin ? CandidatePlan::kBuild : CandidatePlan::kDescend;
}

// World centre of leaf i of a sphere-tree collider, by the expression the world-frame descent
// (descendAlone, tree_terrain_descent.cpp) uses, so that every place that tests a leaf on its own
// gets the same bits (a one-level tree's root leaf stands at the body origin). Always inlined: GCC
// leaves it a call in the leaf loops, and inlining it takes a Lv 6 crosses run from 1,450 to 1,320
// ms (3 interleaved runs each).
inline __attribute__((always_inline)) Vec3 leafWorldCenter(const Collider& c, std::uint32_t i) {
  const SphereTree& tree = *c.tree;
  return tree.leafLevel() == 0 ? c.x : Vec3(c.x + c.R * tree.leaves().centers[i]);
}

// Height of the point c above plane collider p, by the one expression every plane test uses
// (the descent, its candidates and the reduction from them must agree to the bit).
inline double planeHeight(const Collider& p, const Vec3& c) { return p.normal.dot(c) - p.offset; }

// Body-body descent (tree_tree_descent.cpp). `memo`: the pair's candidates (null: none).
std::uint64_t collideTreeTree(const Collider& a, const Collider& b, std::vector<Contact>& out);
std::uint64_t collideTreeTree(const Collider& a, const Collider& b, std::vector<Contact>& out,
                              PairCandidates* memo);

// Sphere tree against the plane (tree_plane_descent.cpp).
std::uint64_t collideTreePlane(const Collider& a, const Collider& p, std::vector<Contact>& out);
std::uint64_t collideTreePlane(const Collider& a, const Collider& p, std::vector<Contact>& out,
                               PairCandidates* memo);
// The contacts handed to `patch` and reduced there into `out` (served candidates: reduced
// without computing every contact, servePlanePatch). Adds the leaf contacts to leafContacts.
std::uint64_t collideTreePlanePatch(const Collider& a, const Collider& p, PairCandidates* memo,
                                    PlanePatch& patch, std::vector<Contact>& out,
                                    std::uint64_t& leafContacts);
// The reduction of a body's plane contacts from its candidates when they hold
// (served_plane_patch.cpp): h0, m and slack as treePlaneDescent hands them to its `serve`.
std::uint64_t servePlanePatch(const Collider& a, const Collider& p, const PairCandidates& memo,
                              double h0, const Vec3& m, double slack, std::vector<Contact>& out,
                              std::uint64_t& leafContacts);

// Sphere tree against the terrain (tree_terrain_descent.cpp).
std::uint64_t collideTreeHeightfield(const Collider& a, const Collider& t,
                                     std::vector<Contact>& out);
std::uint64_t collideTreeHeightfield(const Collider& a, const Collider& t,
                                     std::vector<Contact>& out, PairCandidates* memo);

}  // namespace vf
