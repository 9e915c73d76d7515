// Shared by the scene, ground and sky fragment shaders (included with #include "common.glsl"):
// the sky gradient, the distance fade into it, and the lighting model. Colours are linear RGB;
// present.frag applies the highlight shoulder and the sRGB encoding.

uniform vec3 uCameraPos;             // m
uniform vec3 uSunDir;                // unit, towards the sun
uniform vec3 uFillDir;               // unit, 25 degrees high on the side away from the sun
uniform vec3 uSunLight;              // light on a surface facing the sun ([light] intensity x color)
uniform vec3 uSkyLight;              // the sky's light on a surface facing up ([light] sky)
uniform vec3 uAmbientLight;          // light from the surroundings ([light] ambient)
uniform float uFadeStart;            // m from the camera: things start fading into the sky...
uniform float uFadeEnd;              // ...and are sky from here on
uniform sampler2DShadow uShadowMap;  // sun depth, compared in the sampler
uniform mat4 uLightViewProjection;   // world -> sun clip space
uniform float uShadowTexel;          // m per shadow-map texel
uniform float uShadowBias;           // constant depth bias, shadow-map depth units
uniform float uShadowFilter;         // offset of the filter's taps along each axis, uv units

// Sky gradient. The formula is restated in tests/render/readback_test.cpp: change both.
const vec3 kZenith = vec3(0.170, 0.320, 0.660);
const vec3 kHorizon = vec3(0.700, 0.760, 0.840);
const vec3 kBelowHorizon = vec3(0.560, 0.590, 0.620);

// Sky colour along unit direction d: only its elevation matters. Above the horizon a cubic
// ease from haze to deep blue; below it the haze darkens quickly to the colour the floor fades
// into.
vec3 skyColor(vec3 d) {
  float e = clamp(d.z, -1.0, 1.0);
  if (e >= 0.0) {
    float u = 1.0 - e;
    return mix(kHorizon, kZenith, 1.0 - u * u * u);
  }
  return mix(kHorizon, kBelowHorizon, min(-e * 8.0, 1.0));
}

// Aerial perspective: far surfaces dissolve into the sky behind them, so the floor has no
// hard edge and its grid fades with distance.
vec3 fadeIntoSky(vec3 color, vec3 worldPos) {
  vec3 d = worldPos - uCameraPos;
  float dist = length(d);
  return mix(color, skyColor(d / dist), smoothstep(uFadeStart, uFadeEnd, dist));
}

// Fraction of the sun visible from surface point p with unit normal n (cosine = n . sun > 0).
float sunVisibility(vec3 p, vec3 n, float cosine) {
#ifdef VF_UNSHADOWED
  // The variant the renderer draws only where none of the lookups below can read a texel that
  // a caster covers (RedrawTracker::floorShadows): there each reads the cleared map, passes,
  // and the sum is exactly 4 / 4 = 1.0. llvmpipe runs both sides of a branch, so a runtime
  // test would save nothing; a separate program does.
  return 1.0;
#else
  // Normal offset instead of a large depth bias: the lookup point moves off the surface by
  // about a texel, more at grazing angles where one texel spans a long stretch of surface.
  // That removes acne without pushing shadows away from where bodies touch the floor
  // (peter-panning), which a depth bias of the same strength would.
  float tangent = sqrt(max(1.0 - cosine * cosine, 0.0)) / max(cosine, 0.05);
  vec3 q = p + n * uShadowTexel * (1.0 + min(tangent, 3.0));
  vec3 s = (uLightViewProjection * vec4(q, 1.0)).xyz * 0.5 + 0.5;
  if (s.z >= 1.0) return 1.0;
  // Four 2x2 bilinear comparisons at (+-a, +-a), a = 0.95 texel: along each axis the filter
  // is two one-texel tents 2a apart, spread as widely (0.95 texel root mean square offset) as
  // a 12-tap Poisson disc of radius 1.6 texels. On llvmpipe the lookups are the largest cost of
  // a frame: against that disc the whole crosses clip draws 1.16x faster, and the frames differ
  // only on penumbrae (PSNR 55-73 dB; README, "Rendering speed").
  float z = s.z - uShadowBias;
  float lit = texture(uShadowMap, vec3(s.x - uShadowFilter, s.y - uShadowFilter, z)) +
              texture(uShadowMap, vec3(s.x + uShadowFilter, s.y - uShadowFilter, z)) +
              texture(uShadowMap, vec3(s.x - uShadowFilter, s.y + uShadowFilter, z)) +
              texture(uShadowMap, vec3(s.x + uShadowFilter, s.y + uShadowFilter, z));
  return lit * 0.25;
#endif
}

// Lit colour of a surface with linear albedo at p, unit normal n (render/light.h states the
// model): the sun (shadowed), the sky's light by how much of the sky the surface faces, the
// surroundings' light from everywhere and as much again from the side away from the sun (an
// unshadowed fill, so faces turned from the sun keep their facets), a faint sun highlight.
vec3 shade(vec3 albedo, vec3 p, vec3 n) {
  float cosine = dot(n, uSunDir);
  float sun = 0.0;
  if (cosine > 0.0) sun = cosine * sunVisibility(p, n, cosine);
  vec3 ambient = uSkyLight * (0.5 + 0.5 * n.z) + uAmbientLight * (1.0 + max(dot(n, uFillDir), 0.0));
  vec3 h = normalize(uSunDir + normalize(uCameraPos - p));
  float highlight = sun > 0.0 ? 0.10 * pow(max(dot(n, h), 0.0), 40.0) * (sun / cosine) : 0.0;
  return albedo * (uSunLight * sun + ambient) + uSunLight * highlight;
}
