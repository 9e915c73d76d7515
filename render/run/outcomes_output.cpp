// Per-rock outcomes as CSV and GeoJSON (nlohmann-json writes the JSON).
#include "render/run/outcomes_output.h"

#include <cinttypes>
#include <nlohmann/json.hpp>

#include "sim/ground/rock_fall.h"

namespace vf {
namespace {

// World -> the DEM file's coordinates (a scene's [ground] offset undone).
Vec3 toDem(const World& world, const Vec3& p) {
  return world.def().terrain ? worldToDem(*world.def().terrain, p) : p;
}

}  // namespace

void writeOutcomesCsv(std::FILE* out, const World& world, const RockFall& rockFall) {
  std::fprintf(out,
               "body,state,release_time_s,release_x,release_y,release_z,end_time_s,end_x,end_y,"
               "end_z,runout_m,reach_angle_deg,max_speed_mps,max_translational_energy_j,"
               "max_rotational_energy_j,max_jump_height_m,bounces\n");
  const auto& rocks = rockFall.outcomes();
  for (std::size_t i = 0; i < rocks.size(); ++i) {
    const RockOutcome& r = rocks[i];
    if (!r.released) continue;
    const Vec3 a = toDem(world, r.release), b = toDem(world, r.end);
    std::fprintf(
        out, "%zu,%s,%.6f,%.4f,%.4f,%.4f,%.6f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.6g,%.6g,%.4f,%d\n", i,
        rockStateName(r.state), r.releaseTime, a.x(), a.y(), a.z(), r.endTime, b.x(), b.y(), b.z(),
        r.runout(), r.reachAngleDegrees(), r.maxSpeed, r.maxTranslationalEnergy,
        r.maxRotationalEnergy, r.maxJumpHeight, r.bounces);
  }
}

void writeOutcomesGeoJson(std::FILE* out, const World& world, const RockFall& rockFall) {
  using nlohmann::json;
  json features = json::array();
  const auto& rocks = rockFall.outcomes();
  for (std::size_t i = 0; i < rocks.size(); ++i) {
    const RockOutcome& r = rocks[i];
    if (!r.released) continue;
    json coords = json::array();
    for (const Vec3& p : r.path) {
      const Vec3 q = toDem(world, p);
      coords.push_back({q.x(), q.y(), q.z()});
    }
    const Vec3 a = toDem(world, r.release), b = toDem(world, r.end);
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "LineString"}, {"coordinates", coords}}},
                        {"properties",
                         {{"body", i},
                          {"state", rockStateName(r.state)},
                          {"release_time_s", r.releaseTime},
                          {"release", {a.x(), a.y(), a.z()}},
                          {"end_time_s", r.endTime},
                          {"end", {b.x(), b.y(), b.z()}},
                          {"runout_m", r.runout()},
                          {"reach_angle_deg", r.reachAngleDegrees()},
                          {"max_speed_mps", r.maxSpeed},
                          {"max_translational_energy_j", r.maxTranslationalEnergy},
                          {"max_rotational_energy_j", r.maxRotationalEnergy},
                          {"max_jump_height_m", r.maxJumpHeight},
                          {"bounces", r.bounces},
                          {"message", r.message}}}});
  }
  json doc = {{"type", "FeatureCollection"}, {"features", features}};
  // GeoJSON 2008's named CRS member (RFC 7946 dropped it and assumes WGS 84; GIS tools still
  // read it, and the paths are in the DEM's projected coordinates, not WGS 84).
  if (world.def().terrain && !world.def().terrain->crsName.empty())
    doc["crs"] = {{"type", "name"}, {"properties", {{"name", world.def().terrain->crsName}}}};
  const std::string text = doc.dump(1) + "\n";
  std::fputs(text.c_str(), out);
}

}  // namespace vf
