#version 450 core
// Bodies and terrain: mesh-frame positions and normals to world space.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;

uniform mat4 uModel;          // mesh frame -> world
uniform mat3 uNormalMatrix;   // inverse transpose of uModel's 3x3 part
uniform mat4 uViewProjection;

out vec3 vWorldPos;
out vec3 vNormal;

void main() {
  vec4 world = uModel * vec4(aPosition, 1.0);
  vWorldPos = world.xyz;
  vNormal = uNormalMatrix * aNormal;
  gl_Position = uViewProjection * world;
}
