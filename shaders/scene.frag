#version 450 core
// Bodies (uSurface 0), terrain (1, steep slopes turn to rock) and unlit overlays (2).
#include "common.glsl"

in vec3 vWorldPos;
in vec3 vNormal;

uniform vec3 uColor;  // linear RGB albedo
uniform int uSurface;
#ifdef VF_DRAPED
// The variant for terrain with a picture draped on it (uSurface 1): sRGB texels read as linear
// albedo, mixed over the slope colours by their coverage (alpha). uDrapeRect: world x, y of its
// south-west corner and its width and height, m.
uniform sampler2D uDrape;
uniform vec4 uDrapeRect;
#endif

out vec4 fragColor;

const vec3 kDry = vec3(0.23, 0.19, 0.12);    // bare earth and scree on moderate slopes
const vec3 kRock = vec3(0.16, 0.155, 0.15);  // rock on steep ones

// A value in [0, 1) for lattice point c: an integer hash (exact, so every GL gives the same).
float lattice(ivec2 c) {
  uint h = (uint(c.x) * 0x8da6b343u) ^ (uint(c.y) * 0xd8163841u);
  h = (h ^ (h >> 16)) * 0x7feb352du;
  h = (h ^ (h >> 15)) * 0x846ca68bu;
  h ^= h >> 16;
  return float(h >> 8) / 16777216.0;
}

// Smooth value noise of period-free lattice values, in [0, 1).
float valueNoise(vec2 p) {
  vec2 i = floor(p), f = p - i;
  vec2 u = f * f * (3.0 - 2.0 * f);
  ivec2 c = ivec2(i);
  return mix(mix(lattice(c), lattice(c + ivec2(1, 0)), u.x),
             mix(lattice(c + ivec2(0, 1)), lattice(c + ivec2(1, 1)), u.x), u.y);
}

// Grain of the ground at world point p (x, y, m), about -1..1: value noise at wavelengths of
// 1, 4, 16 and 64 m, each faded out before it gets finer than about three pixels (where it
// would alias into shimmer). It gives a terrain without a picture on it a texture at every
// scale, so it reads as ground and shows its size, as the floor's grid does.
float grain(vec2 p) {
  float footprint = max(length(fwidth(p)), 1e-6);  // m per pixel
  float sum = 0.0;
  float wavelength = 1.0;
  for (int k = 0; k < 4; ++k) {
    float visible = 1.0 - smoothstep(0.1, 0.35, footprint / wavelength);
    sum += visible * (valueNoise(p / wavelength + vec2(float(k) * 37.0)) - 0.5);
    wavelength *= 4.0;
  }
  return sum;
}

void main() {
  if (uSurface == 2) {
    fragColor = vec4(uColor, 1.0);
    return;
  }
  vec3 n = normalize(vNormal);
  // Open terrain seen from below, or a mesh wound the wrong way: light the side we see.
  if (!gl_FrontFacing) n = -n;
  vec3 albedo = uColor;
  if (uSurface == 1) {
    // n.z is the cosine of the slope: the scene's colour up to about 12 degrees, bare earth by
    // 25, rock beyond 40. The colour shows the slope even where the light does not; the grain
    // frays the borders between them and mottles each.
    // Height mixed in, so steep faces get grain along their height too.
    float g = grain(vWorldPos.xy + vec2(0.6, -0.6) * vWorldPos.z);
    float steep = 1.0 - n.z + 0.04 * g;
    albedo = mix(uColor, kDry, smoothstep(0.02, 0.09, steep));
    albedo = mix(albedo, kRock, smoothstep(0.15, 0.25, steep));
    albedo *= 1.0 + 0.35 * g;
#ifdef VF_DRAPED
    vec4 texel = texture(uDrape, (vWorldPos.xy - uDrapeRect.xy) / uDrapeRect.zw);
    albedo = mix(albedo, texel.rgb, texel.a);
#endif
  }
  fragColor = vec4(fadeIntoSky(shade(albedo, vWorldPos, n), vWorldPos), 1.0);
}
