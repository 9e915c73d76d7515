// Clips with a moving camera drawn and encoded at 1280x720, where incremental redraw cannot
// help: the cliff's chase ([camera] of scenes/cliff.toml, frames 0-89) and an orbit round the
// crosses ([cameras.orbit] of scenes/crosses.toml, frames 270-359, while the heap grows). Each
// scene is simulated once, untimed; then, for each clip:
//   1. draw and encode into an MP4 as `voxfall render` does (the encoder on its own thread):
//      the benchmark's time, `fps` and `cpu_ms` (process CPU per frame, both threads);
//   2. draw only, keeping the frames: `render_fps`;
//   3. encode only those frames: `encode_fps`;
//   4. draw again with the GL waited for after each pass (RenderSettings::timePasses):
//      `shadow_ms`, `scene_ms`, `floor_ms`, `present_ms`, `readback_ms` per frame.
// Environment: FRAMES (default 90) changes the clip length; SHADERS names another folder of
// shaders (to compare a change of them in one session); SAMPLES (default 4) the MSAA samples.
// docs/performance.md, "Rendering speed", says how to read them. Run:
// build/tests/bench/render_bench
#include <benchmark/benchmark.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/gl/shader_program.h"
#include "render/output/output_file.h"
#include "render/output/video_encoder.h"
#include "render/scene_playback.h"
#include "sim/scene/scene.h"

namespace {

constexpr int kWidth = 1280, kHeight = 720;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double cpuNow() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

int clipFrames() {
  const char* text = std::getenv("FRAMES");
  const int n = text ? std::atoi(text) : 90;
  return n > 0 ? n : 90;
}

vf::gl::Context& context() {
  static const std::unique_ptr<vf::gl::Context> c = vf::gl::createContext(vf::gl::Backend::osmesa);
  return *c;
}

vf::gl::RenderSettings settings(bool timePasses) {
  vf::gl::RenderSettings s;
  s.width = kWidth;
  s.height = kHeight;
  const char* shaders = std::getenv("SHADERS");
  s.shaderDir = vf::gl::findShaderDir(shaders ? shaders : "");
  if (const char* samples = std::getenv("SAMPLES")) s.samples = std::atoi(samples);
  s.timePasses = timePasses;
  return s;
}

std::string scratchVideo() {
  return (std::filesystem::temp_directory_path() /
          ("voxfall_render_bench_" + std::to_string(::getpid()) + ".mp4"))
      .string();
}

vf::VideoSettings video() {
  vf::VideoSettings v;
  v.width = kWidth;
  v.height = kHeight;
  return v;
}

void Clip(benchmark::State& state, const char* scene, const char* camera, int first) {
  vf::SceneSpec spec = vf::loadScene(std::string(VOXFALL_SOURCE_DIR) + "/scenes/" + scene);
  vf::selectCamera(spec, camera);
  vf::ScenePlayback playback(spec, kWidth, kHeight);
  playback.simulate(false);
  const int last = std::min(first + clipFrames(), playback.frameCount()) - 1;
  const int frames = last - first + 1;
  const std::string path = scratchVideo();
  vf::gl::Context& gl = context();

  for (auto _ : state) {
    // 1. Draw and encode, as `voxfall render` does.
    double pipeline = 0, cpu = 0, redrawn = 0;
    {
      vf::gl::Renderer renderer(gl, settings(false));
      vf::VideoEncoder encoder(path, video(), vf::replaceOutputs());
      vf::Image image;
      const double start = now(), cpuStart = cpuNow();
      for (int k = first; k <= last; ++k) {
        playback.draw(renderer, k, image);
        redrawn += renderer.redrawnFraction();
        encoder.write(k, image);
      }
      encoder.finish();
      pipeline = now() - start;
      cpu = cpuNow() - cpuStart;
    }
    // 2. Draw only.
    std::vector<vf::Image> images(static_cast<std::size_t>(frames));
    double render = 0;
    {
      vf::gl::Renderer renderer(gl, settings(false));
      const double start = now();
      for (int k = first; k <= last; ++k)
        playback.draw(renderer, k, images[static_cast<std::size_t>(k - first)]);
      render = now() - start;
    }
    // 3. Encode only.
    double encode = 0;
    {
      vf::VideoEncoder encoder(path, video(), vf::replaceOutputs());
      const double start = now();
      for (int k = first; k <= last; ++k)
        encoder.write(k, images[static_cast<std::size_t>(k - first)]);
      encoder.finish();
      encode = now() - start;
    }
    images.clear();
    // 4. Draw with each pass timed.
    vf::gl::PassTimes passes;
    {
      vf::gl::Renderer renderer(gl, settings(true));
      vf::Image image;
      for (int k = first; k <= last; ++k) playback.draw(renderer, k, image);
      passes = renderer.passTimes();
    }
    state.SetIterationTime(pipeline);
    const double perFrame = 1000.0 / frames;  // s over the clip -> ms per frame
    state.counters["frames"] = frames;
    state.counters["fps"] = frames / pipeline;
    state.counters["cpu_ms"] = cpu * perFrame;
    state.counters["pct_redrawn"] = 100 * redrawn / frames;
    state.counters["render_fps"] = frames / render;
    state.counters["encode_fps"] = frames / encode;
    state.counters["shadow_ms"] = passes.shadow * perFrame;
    state.counters["scene_ms"] = passes.scene * perFrame;
    state.counters["floor_ms"] = passes.floor * perFrame;
    state.counters["present_ms"] = passes.present * perFrame;
    state.counters["readback_ms"] = passes.readback * perFrame;
  }
  std::filesystem::remove(path);
}

void CliffChase(benchmark::State& state) { Clip(state, "cliff.toml", "camera", 0); }
void CrossesOrbit(benchmark::State& state) { Clip(state, "crosses.toml", "orbit", 270); }

BENCHMARK(CliffChase)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(CrossesOrbit)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
