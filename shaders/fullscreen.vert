#version 450 core
// One triangle covering the viewport, at the far plane (depth 1), from gl_VertexID alone.
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  gl_Position = vec4(p, 1.0, 1.0);
}
