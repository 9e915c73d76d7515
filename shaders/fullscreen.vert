#version 450 core
// One triangle covering the viewport, at the far plane (depth 1), from gl_VertexID alone,
// with the view ray through each corner for the sky (present.frag).
uniform mat4 uInverseViewProjection;  // of projection * view rotation (no translation)

// The ray is an affine function of the window position (the inverse projection's w is the
// same at every point of the far plane), so interpolating it linearly in the window gives each
// pixel its own ray: the fragment shader saves a matrix product and a division per pixel,
// which on llvmpipe were most of the sky's cost.
noperspective out vec3 vRay;

void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  gl_Position = vec4(p, 1.0, 1.0);
  vec4 ray = uInverseViewProjection * vec4(p, 1.0, 1.0);
  vRay = ray.xyz / ray.w;
}
