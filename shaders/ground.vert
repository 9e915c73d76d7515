#version 450 core
// The floor plane z = height: an axis-aligned rectangle of it (a square around the camera),
// made from gl_VertexID alone (no buffer).
uniform vec2 uGroundMin;     // m, x and y of the rectangle's corners
uniform vec2 uGroundMax;
uniform float uGroundHeight; // m
uniform mat4 uViewProjection;

out vec3 vWorldPos;

void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));  // strip order
  vec3 p = vec3(mix(uGroundMin, uGroundMax, corner), uGroundHeight);
  vWorldPos = p;
  gl_Position = uViewProjection * vec4(p, 1.0);
}
