// Releases: bodies that join the world at their release time (the paper's examples 2-4 throw or
// drop blocks one after another; voxfall's emitters write that down), each optionally lifted
// so that it starts `drop_height` above what lies under it. World::addBody (a body released at
// once) and World::releaseBodies (after every step) use this; placement is a function of the
// state alone, so releases keep the trajectory deterministic.
#pragma once

#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"

namespace vf {

struct Heightfield;

// The ground a released body may rest on: the floor plane z = h and the terrain, either absent.
struct ReleaseGround {
  std::optional<double> floorHeight;
  const Heightfield* terrain = nullptr;
};

// How far to raise body `id` (vertically, m) so that its lowest mesh point is `clearance` above
// the highest point under its footprint: the floor, the terrain directly under its vertices
// (Heightfield::surfaceUnder, not the highest grid node near it), and the bodies of the pile,
// those that touched something in the last step (`lastContacts`; sleeping bodies; before the
// first step, `firstStep`, every active body); then above every other active body whose box it
// would otherwise be born inside. Boxes are the meshes' bounds grown by both bodies' leaf radii,
// since leaf spheres stick out of a mesh's bounds by up to their radius: a body placed clear of
// them is clear of the spheres the narrow phase tests. 0 when nothing lies under it (no floor,
// no terrain, no body below); negative when it starts higher than asked (it is lowered).
double releaseLift(int id, double clearance, const std::vector<BodyInfo>& bodies,
                   const std::vector<BodyState>& states, const std::vector<Contact>& lastContacts,
                   bool firstStep, const ReleaseGround& ground);

// How far to raise body `id` (vertically, m, >= 0) so that its mesh bounds lie above the bounds
// of every active body they would meet, each grown by both bodies' leaf radii (as in
// releaseLift): clear of their leaf spheres. Used for a release that would be born inside
// another body (`clear_release`); 0 when the bounds meet none.
double releaseClearLift(int id, const std::vector<BodyInfo>& bodies,
                        const std::vector<BodyState>& states);

// True if body `id`'s leaf spheres touch those of another active body: an emitter aimed into a
// pile (counted in the run's statistics, StepStats::overlappingReleases).
bool overlapsActiveBody(int id, const std::vector<BodyInfo>& bodies,
                        const std::vector<BodyState>& states);

}  // namespace vf
