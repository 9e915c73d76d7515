// The narrow phase: which pair of colliders is tested how (the [type][type] table), and the
// stage of a step that poses every moving body's collider, lists the collider pairs, hands each
// sphere-tree pair its temporal-coherence candidates and runs the pairs on the worker pool.
// The sphere-tree descents of fig. 3 live beside it: tree_tree_descent.cpp (body-body),
// tree_plane_descent.cpp and served_plane_patch.cpp (body-plane), tree_terrain_descent.cpp
// (body-terrain); what they share is in descent_common.h. The polygon collider is
// polygon_contact.cpp.
#include "sim/collide/narrow_phase.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "sim/collide/contact_reduction.h"
#include "sim/collide/descent_common.h"
#include "sim/collide/polygon_contact.h"
#include "sim/core/error.h"
#include "sim/core/worker_pool.h"
#include "sim/shape/convex_polyhedron.h"
#include "sim/shape/shape.h"

namespace vf {
namespace {

using CollideFn = std::uint64_t (*)(const Collider&, const Collider&, std::vector<Contact>&);

// Which pair does what. Rows: type of a (body 1); columns: type of b (body 2). The plane and
// the terrain are always body 2 (they never move), so their rows are empty. A scene uses one
// method for all its bodies (sphere trees or polygons), so the two never meet.
constexpr int kTypes = static_cast<int>(ColliderType::kCount);
constexpr CollideFn kCollide[kTypes][kTypes] = {
    //                  kSphereTree      kPlane               kHeightfield     kPolygon
    /* kSphereTree  */ {collideTreeTree, collideTreePlane, collideTreeHeightfield, nullptr},
    /* kPlane       */ {nullptr, nullptr, nullptr, nullptr},
    /* kHeightfield */ {nullptr, nullptr, nullptr, nullptr},
    /* kPolygon     */
    {nullptr, collidePolygonPlane, collidePolygonHeightfield, collidePolygonPolygon},
};

}  // namespace

// A body's collider of the given type at pose (x, q).
static Collider posedCollider(ColliderType type, int body, const Vec3& x, const Quat& q) {
  Collider c;
  c.type = type;
  c.body = body;
  c.x = x;
  c.R = q.toRotationMatrix();
  return c;
}

Collider sphereTreeCollider(int body, const SphereTree& tree, const Vec3& x, const Quat& q) {
  Collider c = posedCollider(ColliderType::kSphereTree, body, x, q);
  c.tree = &tree;
  return c;
}

Collider polygonCollider(int body, const ConvexPolyhedron& polyhedron, const Vec3& x,
                         const Quat& q) {
  Collider c = posedCollider(ColliderType::kPolygon, body, x, q);
  c.polyhedron = &polyhedron;
  return c;
}

Collider heightfieldCollider(const Heightfield& terrain) {
  Collider c;
  c.type = ColliderType::kHeightfield;
  c.body = kGround;
  c.terrain = &terrain;
  return c;
}

Collider planeCollider(double height) {
  Collider c;
  c.type = ColliderType::kPlane;
  c.body = kGround;
  c.normal = Vec3::UnitZ();
  c.offset = height;
  return c;
}

std::uint64_t collide(const Collider& a, const Collider& b, std::vector<Contact>& out) {
  const CollideFn fn = kCollide[static_cast<int>(a.type)][static_cast<int>(b.type)];
  VF_ASSERT(fn != nullptr);
  return fn(a, b, out);
}

namespace {

// A collider pair to test: a (body 1) and b (body 2).
using Job = std::pair<const Collider*, const Collider*>;
using CacheKey = std::pair<std::uint64_t, std::uint32_t>;  // CandidateCache::pairs' entries

// Scratch reused from call to call (per thread: ensembles step worlds on several), so that
// a step allocates nothing here once warm; for one rock on a terrain, allocating per call
// costs about 5 % of a step's instructions.
struct FindScratch {
  std::vector<Collider> posed;  // each active body's collider, posed once per call
  std::vector<Job> jobs;
  std::vector<PairCandidates*> memo;
  std::vector<std::vector<Contact>> found;
  std::vector<ContactCounts> counts;
  std::vector<CacheKey> kept;  // the cache's next pair list
};

// Each body's collider once (a rock is in about three jobs a step, and a job holding two
// whole colliders takes 320 bytes to write and to stride over).
void poseColliders(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                   WorkerPool* pool, std::vector<Collider>& posed) {
  posed.resize(bodies.size());
  WorkerPool::forRanges(
      pool, static_cast<int>(bodies.size()), WorkerPool::kBodiesPerRange, [&](int lo, int hi) {
        for (int i = lo; i < hi; ++i) {
          if (!bodies[i].active) continue;
          const Shape& s = *bodies[i].shape;
          posed[i] = s.polyhedron ? polygonCollider(i, *s.polyhedron, states[i].x, states[i].q)
                                  : sphereTreeCollider(i, *s.tree, states[i].x, states[i].q);
        }
      });
}

// The collider pairs of this step, in the order their contacts must come out: the body pairs,
// then each moving body with the plane and with the terrain (null: none).
void listJobs(const std::vector<BodyInfo>& bodies, const std::vector<BodyPair>& pairs,
              const std::vector<Collider>& posed, const Collider* plane, const Collider* field,
              std::vector<Job>& jobs) {
  jobs.clear();
  for (const BodyPair& p : pairs)  // a pair of which nothing moves (asleep, static) has no news
    if (bodies[p.a].moves() || bodies[p.b].moves()) jobs.emplace_back(&posed[p.a], &posed[p.b]);
  if (plane)
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].moves()) jobs.emplace_back(&posed[i], plane);
  if (field)
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].moves()) jobs.emplace_back(&posed[i], field);
}

// Whether job k is a sphere-tree pair (one that keeps candidates).
bool treeJob(const std::vector<Job>& jobs, std::size_t k) {
  return jobs[k].first->type == ColliderType::kSphereTree &&
         jobs[k].second->type != ColliderType::kPolygon;
}

// The body pairs' candidates. Their jobs come first, in the order of `pairs` (by a, then b), so
// the cache's sorted list is merged with them. Returns the number of body-pair jobs.
std::size_t matchPairCandidates(const std::vector<Job>& jobs, CandidateCache& candidates,
                                std::vector<CacheKey>& kept, std::vector<PairCandidates*>& memo) {
  std::vector<CacheKey>& old = candidates.pairs;
  std::vector<PairCandidates>& slots = candidates.slots;
  std::vector<std::uint32_t>& freeSlots = candidates.freeSlots;
  kept.clear();
  std::size_t k = 0, o = 0;
  for (; k < jobs.size() && jobs[k].second->type != ColliderType::kPlane &&
         jobs[k].second->type != ColliderType::kHeightfield;
       ++k) {
    if (!treeJob(jobs, k)) continue;
    const std::uint64_t key = (static_cast<std::uint64_t>(jobs[k].first->body) << 32) |
                              static_cast<std::uint32_t>(jobs[k].second->body);
    for (; o < old.size() && old[o].first < key; ++o)  // pairs gone since: their slots freed
      freeSlots.push_back(old[o].second);
    if (o < old.size() && old[o].first == key) {
      kept.push_back(old[o++]);
    } else if (!freeSlots.empty()) {
      kept.emplace_back(key, freeSlots.back());
      freeSlots.pop_back();
      slots[kept.back().second].restart();
    } else {
      kept.emplace_back(key, static_cast<std::uint32_t>(slots.size()));
      slots.emplace_back();
    }
  }
  for (; o < old.size(); ++o) freeSlots.push_back(old[o].second);
  old.swap(kept);
  // `slots` is complete now: pointers into it stay valid for this call.
  for (std::size_t k2 = 0, p = 0; k2 < k; ++k2)
    if (treeJob(jobs, k2)) memo[k2] = &slots[old[p++].second];
  return k;
}

// The ground pairs' candidates (jobs from `first` on), by body. Only moving bodies have ground
// jobs: a body that does not move this call (asleep, gone) starts afresh when it moves again.
void matchGroundCandidates(const std::vector<BodyInfo>& bodies, const std::vector<Job>& jobs,
                           std::size_t first, CandidateCache& candidates,
                           std::vector<PairCandidates*>& memo) {
  const std::size_t n = bodies.size();
  candidates.plane.resize(n);
  candidates.terrain.resize(n);
  for (std::size_t k = first; k < jobs.size(); ++k) {
    if (!treeJob(jobs, k)) continue;
    std::vector<PairCandidates>& ground =
        jobs[k].second->type == ColliderType::kPlane ? candidates.plane : candidates.terrain;
    memo[k] = &ground[static_cast<std::size_t>(jobs[k].first->body)];
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!bodies[i].moves())
      for (PairCandidates* c : {&candidates.plane[i], &candidates.terrain[i]})
        if (c->holds || c->hasLast) c->restart();
}

// One job's contacts appended to sink, reduced if asked: each collider pair on its own, by
// the thread that found them. A sphere tree on the plane is reduced as its contacts come
// (PlanePatch: the same representatives, without storing every leaf contact).
void runJob(const Collider& a, const Collider& b, PairCandidates* m, bool reduce,
            std::vector<Contact>& sink, ContactCounts& counts) {
  if (reduce && a.type == ColliderType::kSphereTree && b.type == ColliderType::kPlane) {
    static thread_local PlanePatch patch;
    counts.sphereTests += collideTreePlanePatch(a, b, m, patch, sink, counts.leafContacts);
    return;
  }
  const std::size_t begin = sink.size();
  if (!m)
    counts.sphereTests += collide(a, b, sink);
  else if (b.type == ColliderType::kPlane)
    counts.sphereTests += collideTreePlane(a, b, sink, m);
  else if (b.type == ColliderType::kHeightfield)
    counts.sphereTests += collideTreeHeightfield(a, b, sink, m);
  else
    counts.sphereTests += collideTreeTree(a, b, sink, m);
  counts.leafContacts += sink.size() - begin;
  if (reduce) reducePairContacts(sink, begin);
}

// Fewer collider pairs than this per thread are not worth waking a worker for (that costs about
// as much as a few dozen sphere-tree descents at rest).
constexpr int kJobsPerThread = 16;
// Blocks of work per thread: enough that a thread that drew cheap blocks takes more.
constexpr int kBlocksPerThread = 16;

// Blocks of consecutive jobs, each into its own list, run by the pool's threads; the lists
// are appended in block order, so the contacts are exactly the serial ones in the serial
// order whatever the thread count. (Jobs differ in cost by orders of magnitude, a rock's pile
// against a rock in flight: one fixed half per thread leaves one of them idle.)
ContactCounts runJobs(const std::vector<Job>& jobs, const std::vector<PairCandidates*>& memo,
                      bool reduce, WorkerPool* pool, FindScratch& scratch,
                      std::vector<Contact>& out) {
  auto run = [&](std::size_t k, std::vector<Contact>& sink, ContactCounts& counts) {
    runJob(*jobs[k].first, *jobs[k].second, memo[k], reduce, sink, counts);
  };
  const int workers =
      pool ? std::max(
                 1, std::min<int>(pool->threads(), static_cast<int>(jobs.size() / kJobsPerThread)))
           : 1;
  ContactCounts total;
  if (workers == 1) {
    for (std::size_t k = 0; k < jobs.size(); ++k) run(k, out, total);
    return total;
  }
  const int blocks = std::min<int>(static_cast<int>(jobs.size()), workers * kBlocksPerThread);
  std::vector<std::vector<Contact>>& found = scratch.found;
  if (found.size() < static_cast<std::size_t>(blocks)) found.resize(blocks);
  for (std::vector<Contact>& f : found) f.clear();
  std::vector<ContactCounts>& counts = scratch.counts;
  counts.assign(blocks, ContactCounts{});
  pool->run(blocks, [&](int c) {
    const std::size_t begin = jobs.size() * c / blocks, end = jobs.size() * (c + 1) / blocks;
    for (std::size_t k = begin; k < end; ++k) run(k, found[c], counts[c]);
  });
  for (int c = 0; c < blocks; ++c) {
    out.insert(out.end(), found[c].begin(), found[c].end());
    total.sphereTests += counts[c].sphereTests;
    total.leafContacts += counts[c].leafContacts;
  }
  return total;
}

}  // namespace

ContactCounts findContacts(const std::vector<BodyInfo>& bodies,
                           const std::vector<BodyState>& states, const std::vector<BodyPair>& pairs,
                           const std::optional<double>& groundHeight, const Heightfield* terrain,
                           WorkerPool* pool, std::vector<Contact>& out, CandidateCache* candidates,
                           bool reduce) {
  static thread_local FindScratch scratch;
  poseColliders(bodies, states, pool, scratch.posed);
  const Collider plane = groundHeight ? planeCollider(*groundHeight) : Collider{};
  const Collider field = terrain ? heightfieldCollider(*terrain) : Collider{};
  std::vector<Job>& jobs = scratch.jobs;
  listJobs(bodies, pairs, scratch.posed, groundHeight ? &plane : nullptr,
           terrain ? &field : nullptr, jobs);
  // Each sphere-tree pair's candidates, found (or made) here, before any thread runs.
  std::vector<PairCandidates*>& memo = scratch.memo;
  memo.assign(jobs.size(), nullptr);
  if (candidates) {
    const std::size_t groundJobs = matchPairCandidates(jobs, *candidates, scratch.kept, memo);
    matchGroundCandidates(bodies, jobs, groundJobs, *candidates, memo);
  }
  const ContactCounts total = runJobs(jobs, memo, reduce, pool, scratch, out);
  if (candidates)
    for (const PairCandidates* m : memo)
      if (m) ++(m->served ? candidates->served : candidates->descents);
  return total;
}

}  // namespace vf
