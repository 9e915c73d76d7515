// The polygon collider: the paper's comparison method ("old method", digest section 7), contact
// between convex polyhedra after Baraff's SIGGRAPH course notes, registered in the narrow
// phase's [type][type] table beside the sphere tree. See polygon_contact.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/collide/narrow_phase.h"

namespace vf {

// Features closer than this fraction of the smaller body's bounding radius count as touching
// (Baraff's contact tolerance): a body resting on another is found in contact every step.
constexpr double kPolygonContactMargin = 1e-3;

// Vertex-face and edge-edge contacts of two convex polyhedra (both colliders kPolygon; a is the
// paper's body 1). Returns the feature tests made (vertex-triangle and edge-edge pairs).
std::uint64_t collidePolygonPolygon(const Collider& a, const Collider& b,
                                    std::vector<Contact>& out);
// A polyhedron's vertices against the floor plane. Returns the vertices tested.
std::uint64_t collidePolygonPlane(const Collider& a, const Collider& plane,
                                  std::vector<Contact>& out);
// A polyhedron's vertices against the terrain. Returns the vertices tested.
std::uint64_t collidePolygonHeightfield(const Collider& a, const Collider& terrain,
                                        std::vector<Contact>& out);

}  // namespace vf
