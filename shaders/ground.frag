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

#ifdef VF_ALPHA
// The variant for frames with a transparent background (RenderSettings::alpha): the floor
// keeps only its shadows, as black at the opacity that darkens what lies behind it as much as
// the shadow darkens the floor: 1 - shaded / unshadowed, by Rec. 709 luminance, where
// unshadowed gives back the sun's direct light that the shadow map took away. It fades out
// with the floor's fade into the sky. Written as 2 + opacity: present.frag reads alpha from 2
// up as the floor's (bodies write 1, and empty samples stay 0).
float shadowOpacity(vec3 albedo, vec3 shaded) {
  vec3 n = vec3(0.0, 0.0, 1.0);
  float cosine = dot(n, uSunDir);
  if (cosine <= 0.0) return 0.0;
  float lost = 1.0 - sunVisibility(vWorldPos, n, cosine);
  vec3 unshadowed = shaded + albedo * uSunLight * cosine * lost;
  const vec3 kLuma = vec3(0.2126, 0.7152, 0.0722);
  float opacity = 1.0 - dot(shaded, kLuma) / max(dot(unshadowed, kLuma), 1e-6);
  float far = smoothstep(uFadeStart, uFadeEnd, length(vWorldPos - uCameraPos));
  return clamp(opacity, 0.0, 1.0) * (1.0 - far);
}
#endif

void main() {
  vec3 albedo = kFloor;
  albedo = mix(albedo, kMinorLine, gridLines(vWorldPos.xy, 0.1, 0.004));
  albedo = mix(albedo, kMajorLine, gridLines(vWorldPos.xy, 1.0, 0.012));
  vec3 color = shade(albedo, vWorldPos, vec3(0.0, 0.0, 1.0));
#ifdef VF_ALPHA
  fragColor = vec4(0.0, 0.0, 0.0, 2.0 + shadowOpacity(albedo, color));
#else
  fragColor = vec4(fadeIntoSky(color, vWorldPos), 1.0);
#endif
}
