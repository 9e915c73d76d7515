#version 450 core
// Bodies (uSurface 0), terrain (1, steep slopes turn to rock) and unlit overlays (2).
#include "common.glsl"

in vec3 vWorldPos;
in vec3 vNormal;

uniform vec3 uColor;  // linear RGB albedo
uniform int uSurface;

out vec4 fragColor;

const vec3 kDry = vec3(0.27, 0.21, 0.12);   // bare earth on moderate slopes
const vec3 kRock = vec3(0.19, 0.18, 0.17);  // rock on steep ones

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
    // 25, rock beyond 40. The colour shows the slope even where the light does not.
    float steep = 1.0 - n.z;
    albedo = mix(uColor, kDry, smoothstep(0.02, 0.09, steep));
    albedo = mix(albedo, kRock, smoothstep(0.15, 0.25, steep));
  }
  fragColor = vec4(fadeIntoSky(shade(albedo, vWorldPos, n), vWorldPos), 1.0);
}
