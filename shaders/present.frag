#version 450 core
// Linear HDR scene -> 8-bit output: average the supersamples (if any), roll highlights off
// above 0.8 instead of clipping them, encode sRGB, dither. Restated in
// tests/render/readback_test.cpp: change both.
uniform sampler2D uImage;  // resolved scene, linear RGB
uniform int uSupersample;  // scene pixels per output pixel along each axis
uniform int uDither;       // 1: add the ordered dither

out vec4 fragColor;

// Identity up to 0.8, then an exponential approach to 1.0 (continuous slope at 0.8).
vec3 shoulder(vec3 c) {
  vec3 over = max(c - 0.8, 0.0);
  return min(c, vec3(0.8)) + 0.2 * (1.0 - exp(-over / 0.2));
}

// The sRGB transfer function (IEC 61966-2-1).
vec3 encodeSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  vec3 low = c * 12.92;
  vec3 high = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
  return mix(low, high, step(vec3(0.0031308), c));
}

// 4x4 Bayer matrix, values (0.5 .. 15.5) / 16: a fixed pattern, so frames stay deterministic.
float bayer(ivec2 p) {
  const int m[16] = int[](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);
  return (float(m[(p.y & 3) * 4 + (p.x & 3)]) + 0.5) / 16.0;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 sum = vec3(0.0);
  for (int y = 0; y < uSupersample; ++y) {
    for (int x = 0; x < uSupersample; ++x) {
      sum += texelFetch(uImage, pixel * uSupersample + ivec2(x, y), 0).rgb;
    }
  }
  vec3 c = encodeSrgb(shoulder(sum / float(uSupersample * uSupersample)));
  if (uDither == 1) c += (bayer(pixel) - 0.5) / 255.0;
  fragColor = vec4(c, 1.0);
}
