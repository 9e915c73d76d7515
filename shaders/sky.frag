#version 450 core
// The sky behind everything: skyColor() of the view ray through the pixel centre.
#include "common.glsl"

uniform mat4 uInverseViewProjection;  // of projection * view rotation (no translation)
uniform vec2 uViewportSize;           // pixels

out vec4 fragColor;

void main() {
  vec2 ndc = gl_FragCoord.xy / uViewportSize * 2.0 - 1.0;
  vec4 p = uInverseViewProjection * vec4(ndc, 1.0, 1.0);
  fragColor = vec4(skyColor(normalize(p.xyz / p.w)), 1.0);
}
