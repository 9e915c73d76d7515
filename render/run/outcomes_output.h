// Per-rock outcomes of a rock fall run (RockFall::outcomes(), sim/ground/rock_fall.h) as CSV or
// GeoJSON; the world gives the DEM whose coordinates they are written in.
#pragma once

#include <cstdio>
#include <string>

#include "sim/world.h"

namespace vf {

class RockFall;  // sim/ground/rock_fall.h

// One row per released dynamic body: release point and time, state, stop or exit point and
// time, horizontal runout, reach angle, maximum speed, maximum translational and rotational
// kinetic energy, maximum jump height. Coordinates in the DEM's own (file) coordinates.
void writeOutcomesCsv(std::FILE* out, const World& world, const RockFall& rockFall);
// A FeatureCollection: per rock, its path as a 3-D LineString in the DEM's coordinates (the
// `crs` member names the DEM's CRS when it has an authority code), the CSV's fields as
// properties.
void writeOutcomesGeoJson(std::FILE* out, const World& world, const RockFall& rockFall);

}  // namespace vf
