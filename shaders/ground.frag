#version 450 core
// The floor: a light grey plane with a 1 m grid and 0.1 m minor lines, so the picture shows
// scale; lit and shadowed like everything else and fading into the sky with distance.
#include "common.glsl"

in vec3 vWorldPos;
out vec4 fragColor;

const vec3 kFloor = vec3(0.36, 0.355, 0.34);
const vec3 kMajorLine = vec3(0.17, 0.17, 0.165);
const vec3 kMinorLine = vec3(0.27, 0.267, 0.256);

// Coverage of grid lines `spacing` m apart and `width` m wide at floor point p, anti-aliased
// over one pixel's footprint. Lines thinner than a pixel are drawn one pixel wide but fainter
// (same ink per area), and the whole set fades out where lines would come closer than about
// four pixels, before they alias into moire.
float gridLines(vec2 p, float spacing, float width) {
  vec2 cell = p / spacing;
  vec2 footprint = max(fwidth(cell), vec2(1e-6));  // cells per pixel
  vec2 toLine = abs(fract(cell + 0.5) - 0.5);     // to the nearest line, in cells
  vec2 halfWidth = vec2(0.5 * width / spacing);
  vec2 drawn = max(halfWidth, 0.5 * footprint);
  vec2 line = (1.0 - smoothstep(drawn - 0.5 * footprint, drawn + 0.5 * footprint, toLine)) *
              min(halfWidth / drawn, vec2(1.0));
  float density = 1.0 - smoothstep(0.12, 0.3, max(footprint.x, footprint.y));
  return max(line.x, line.y) * density;
}

void main() {
  vec3 albedo = kFloor;
  albedo = mix(albedo, kMinorLine, gridLines(vWorldPos.xy, 0.1, 0.004));
  albedo = mix(albedo, kMajorLine, gridLines(vWorldPos.xy, 1.0, 0.012));
  vec3 color = shade(albedo, vWorldPos, vec3(0.0, 0.0, 1.0));
  fragColor = vec4(fadeIntoSky(color, vWorldPos), 1.0);
}
