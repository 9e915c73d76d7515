// The light of a scene: a sun fixed in the world, the sky's light and the light of the
// surroundings. `[light]` sets them (sim/scene/scene.h, LightSpec); without a sun direction the
// default one stands in a fixed relation to the automatic camera's azimuth, which is one per
// scene (draw_list.h), so the sun never turns with a camera and every camera of a scene sees
// the same shadows.
#pragma once

#include <optional>

#include "sim/core/math.h"
#include "sim/scene/drawing_spec.h"

namespace vf {

struct Heightfield;  // sim/shape/heightfield.h

// What the shaders light with (shaders/common.glsl, shade()), linear RGB. A surface with unit
// normal n gets sun * max(0, n . toSun) (shadowed) + sky * (1 + n.z) / 2 +
// ambient * (1 + max(0, n . fill)), fill 25 degrees high on the side away from the sun.
struct LightColors {
  Vec3 sun = Vec3(1.75, 1.68, 1.5505);  // intensity x color of the default LightSpec
  Vec3 sky = Vec3(0.23, 0.30, 0.42);
  Vec3 ambient = Vec3(0.17, 0.16, 0.15);
  bool operator==(const LightColors&) const = default;
};

// The light a scene asks for: its colours, and the sun's direction where the scene fixes it.
struct SceneLight {
  std::optional<Vec3> sunDirection;  // unit, towards the sun; none: defaultSunDirection()
  LightColors colors;
};

// The unit vector towards a sun at compass azimuth `azimuthDegrees` (clockwise from +y, the
// grid's north: 90 is +x, east) and `elevationDegrees` above the horizon.
Vec3 sunFromCompass(double azimuthDegrees, double elevationDegrees);

// The default sun for an automatic camera that looks along horizontal direction `view`: 45
// degrees high and 30 degrees counter-clockwise (seen from above) of the direction back towards
// the camera, so behind the camera's right shoulder. Both sides of a box that face the camera are
// lit, unequally (so they read as two faces); shadows fall away from the viewer and a little to
// the left, beside the bodies that cast them; and on a terrain, where the automatic camera
// has the slope falling to the right (terrain_camera.h), the slope faces the sun.
Vec3 defaultSunDirection(const Vec3& view);

// The light `spec` gives: colours from intensity, color, sky and ambient; the sun from azimuth
// and elevation, or from date and time at the centre of `terrain` (sunPosition in
// render/solar_position.h, turned from true north to the grid's north). Throws InputError at
// spec.where when date and time are given and the terrain is missing or has no CRS, or the sun
// is below the horizon then.
SceneLight sceneLight(const LightSpec& spec, const Heightfield* terrain);

}  // namespace vf
