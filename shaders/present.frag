#version 450 core
// Scene target -> 8-bit output, in one pass: average the pixel's samples (MSAA) or sub-pixels
// (supersampling), filling every one the geometry left empty (alpha 0) with the sky along its
// view ray; roll highlights off above 0.8 instead of clipping them; encode sRGB; dither.
// The variant VF_NO_SKY is drawn where the floor covers every sample (floorCovers() in
// render/redraw_region.h): the same pixels without working out the sky. (llvmpipe runs both
// sides of a branch, so only a separate program saves that work.)
// The sky is drawn here rather than as a full-screen pass into the multisampled target: on
// llvmpipe that pass costs a quarter of a frame, all of it spent writing 4 identical samples
// per pixel, and the resolve blit another fifth. Restated in tests/render/readback_test.cpp:
// change both.
#include "common.glsl"

uniform sampler2DMS uScene;   // multisampled scene, linear RGB, alpha 1 where drawn (unit 0)
uniform sampler2D uImage;     // single-sampled scene at uSupersample x the size (unit 1)
uniform int uSamples;         // > 1: read uScene's samples; otherwise uImage's sub-pixels
uniform int uSupersample;     // scene pixels per output pixel along each axis (uImage)
uniform int uDither;          // 1: add the ordered dither
uniform mat4 uInverseViewProjection;  // of projection * view rotation (no translation)
uniform vec2 uSceneSize;              // scene target size in pixels
noperspective in vec3 vRay;           // view ray through the pixel's centre (fullscreen.vert)

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
// Bit-interleaved form of the table {0 8 2 10, 12 4 14 6, 3 11 1 9, 15 7 13 5} (row y, column
// x): no indexed constant array, which llvmpipe would spill to memory per fragment.
float bayer(ivec2 p) {
  int a = (p.x ^ p.y) & 3, b = p.y & 3;
  int m = ((a & 1) << 3) | ((b & 1) << 2) | (a & 2) | ((b >> 1) & 1);
  return (float(m) + 0.5) / 16.0;
}

// c cut to half precision as llvmpipe stores into a half-float target (the 13 low mantissa
// bits dropped: rounding towards zero, for the positive normal values light has here). The sky
// and the sample average get the rounding that going through such targets (a sky pass and a
// resolve blit) would give them, so the frames are byte for byte those of that pipeline.
vec3 roundToHalf(vec3 c) { return uintBitsToFloat(floatBitsToUint(c) & uvec3(0xFFFFE000u)); }

// The sky behind scene pixel position `at` (pixels, centre at +0.5).
vec3 skyAt(vec2 at) {
  vec4 p = uInverseViewProjection * vec4(at / uSceneSize * 2.0 - 1.0, 1.0, 1.0);
  return roundToHalf(skyColor(normalize(p.xyz / p.w)));
}

// The sky behind this output pixel's centre: skyAt(gl_FragCoord.xy) up to rounding.
vec3 skyHere() { return roundToHalf(skyColor(normalize(vRay))); }

#ifdef VF_ALPHA
// A transparent background (RenderSettings::alpha): no sky; alpha is the pixel's coverage,
// each sample counting 1 for a body or the terrain, its shadow's opacity for the floor (written
// as 2 + opacity, black) and 0 where nothing was drawn. The colour is straight, not
// premultiplied: the coverage-weighted mean of the samples, so a pixel wholly on a body has
// the colour the opaque frame gives it.
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 sum = vec3(0.0);
  float cover = 0.0;
  float count;
  if (uSamples > 1) {
    for (int i = 0; i < uSamples; ++i) {
      vec4 c = texelFetch(uScene, pixel, i);
      if (c.a >= 2.0) {
        cover += c.a - 2.0;
      } else if (c.a > 0.0) {
        sum += c.rgb;
        cover += 1.0;
      }
    }
    count = float(uSamples);
  } else {
    for (int y = 0; y < uSupersample; ++y) {
      for (int x = 0; x < uSupersample; ++x) {
        vec4 c = texelFetch(uImage, pixel * uSupersample + ivec2(x, y), 0);
        if (c.a >= 2.0) {
          cover += c.a - 2.0;
        } else if (c.a > 0.0) {
          sum += c.rgb;
          cover += 1.0;
        }
      }
    }
    count = float(uSupersample * uSupersample);
  }
  vec3 c = vec3(0.0);
  if (cover > 0.0) {
    // As the opaque path rounds: the MSAA mean through half precision, the supersampled not.
    vec3 mean = uSamples > 1 ? roundToHalf(sum / cover) : sum / cover;
    c = encodeSrgb(shoulder(mean));
    if (uDither == 1) c += (bayer(pixel) - 0.5) / 255.0;
  }
  fragColor = vec4(c, cover / count);
}
#else
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 sum = vec3(0.0);
  float count;
  if (uSamples > 1) {
    // Every sample of a pixel sees the sky along the pixel centre's ray, as a full-screen
    // pass shaded once per pixel would have written it.
#ifndef VF_NO_SKY
    vec3 sky = skyHere();
#endif
    for (int i = 0; i < uSamples; ++i) {
      vec4 c = texelFetch(uScene, pixel, i);
#ifdef VF_NO_SKY
      sum += c.rgb;
#else
      sum += c.a == 0.0 ? sky : c.rgb;
#endif
    }
    sum = roundToHalf(sum / float(uSamples));
    count = 1.0;
  } else {
    for (int y = 0; y < uSupersample; ++y) {
      for (int x = 0; x < uSupersample; ++x) {
        ivec2 at = pixel * uSupersample + ivec2(x, y);
        vec4 c = texelFetch(uImage, at, 0);
#ifdef VF_NO_SKY
        sum += c.rgb;
#else
        sum += c.a == 0.0 ? skyAt(vec2(at) + 0.5) : c.rgb;
#endif
      }
    }
    count = float(uSupersample * uSupersample);
  }
  vec3 c = encodeSrgb(shoulder(sum / count));
  if (uDither == 1) c += (bayer(pixel) - 0.5) / 255.0;
  fragColor = vec4(c, 1.0);
}
#endif
