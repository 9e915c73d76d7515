// What a scene asks of its pictures: body colours, cameras and light. Plain values read from
// the scene file (sim/scene/scene.h) and drawn by render/ (render/camera.h, render/light.h);
// drawing only, they never change a run. Kept apart from scene.h so that the drawing code sees
// these values without the World and the rest of the scene.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "sim/core/math.h"

namespace vf {

using Color = std::array<float, 3>;  // linear RGB in [0, 1]

// One key of a camera path: where the camera is, what it looks at and its field of view at a
// time. Between keys all three are interpolated smoothly (render/camera.h).
struct CameraKey {
  double time = 0;  // s
  Vec3 position = Vec3::Zero();
  Vec3 lookAt = Vec3::Zero();
  double fovDegrees = 40;
};

// A camera. Which kind follows from the keys given: `path`: a keyframed path; `follow`: a chase
// camera keeping the offset position - look_at from the body (or the group's centroid), with
// an exponential lag of time constant `smoothing`; `position`/`look_at`: a fixed camera;
// neither: the automatic camera, which frames every body still on the ground or terrain.
struct CameraSpec {
  std::string name = "camera";  // "camera" for [camera], NAME for [cameras.NAME]
  bool given = false;           // a view is given (fixed or chase); false: automatic, or the path
  // `position` or `look_at` given: a chase keeps their offset. Without them a chase on a
  // terrain frames its bodies across the slope (render/terrain_camera.h), and elsewhere keeps
  // the default offset.
  bool offsetGiven = false;
  Vec3 position = Vec3(4, -6, 3);
  Vec3 lookAt = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  double fovDegrees = 40;         // vertical
  std::optional<int> followBody;  // body index whose centre of mass the camera looks at
  std::vector<int> followGroup;   // or several bodies: the camera looks at their centroid
  double smoothing = 0;           // s, time constant of the chase camera's lag; 0: rigid
  std::vector<CameraKey> path;    // keys in increasing time; empty: no path
  double minPixels = 0;           // bodies smaller on screen are drawn as markers this wide (px)
  double trailSeconds = 0;        // s of trajectory drawn behind each body; 0: no trails
  std::string where;              // "file:line:column" of the table
};

// A calendar date (the proleptic Gregorian calendar).
struct CivilDate {
  int year = 2000, month = 1, day = 1;
  bool operator==(const CivilDate&) const = default;
};

// [light]: the sun, fixed in the world, and the light of the sky and the surroundings
// (render/light.h; docs/rendering.md, "Light"). Drawing only: it never changes a run.
struct LightSpec {
  // The sun's compass direction, degrees clockwise from north (+y, the DEM's grid north), and
  // its height above the horizon, degrees. Both or neither.
  std::optional<double> azimuthDegrees, elevationDegrees;
  // Or the sun of a date and a UTC time of day at the terrain's location (a georeferenced DEM).
  std::optional<CivilDate> date;
  double utcSeconds = 12 * 3600.0;  // `time`: seconds after 00:00 UTC
  // Light on a surface facing the sun: intensity x color (linear RGB). The defaults are a
  // slightly warm sun about 2.3 times the sky's light.
  double intensity = 1.75;
  Color color{1.0f, 0.96f, 0.886f};
  // The sky's light on a surface facing straight up (none facing down), and the light from
  // the surroundings: half of it from every direction, the other half from the side away from
  // the sun (linear RGB).
  Color sky{0.23f, 0.30f, 0.42f};
  Color ambient{0.17f, 0.16f, 0.15f};
  std::string where;  // "file:line:column" of [light]; empty without one
};

}  // namespace vf
