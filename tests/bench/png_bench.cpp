// PNG compression of one rendered frame: frame 30 of scenes/cubes.toml at 1280x720, drawn
// in-process once at start-up as `voxfall render` draws it. Rows: voxfall's encoder for frames
// (EncodeFrame: libdeflate level 1, rows unfiltered) and for single pictures (EncodePicture:
// level 6), and libpng's simplified writer with its defaults (LibpngDefault: adaptive row
// filters, zlib level 6), the writer `render` used before, for comparison. Counter `bytes`: the
// file's size. Run: build/tests/bench/png_bench
#include <benchmark/benchmark.h>
#include <png.h>

#include <cstring>
#include <string>
#include <vector>

#include "render/gl/gl_context.h"
#include "render/gl/shader_program.h"
#include "render/output/png_writer.h"
#include "render/scene_playback.h"
#include "sim/scene/scene.h"

namespace {

const vf::Image& frame() {
  static const vf::Image image = [] {
    vf::SceneSpec spec = vf::loadScene(std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml");
    auto context = vf::gl::createContext(vf::gl::Backend::osmesa);
    return vf::renderSceneFrames(spec, {30}, *context, vf::gl::findShaderDir()).images.at(0);
  }();
  return image;
}

void encode(benchmark::State& state, vf::PngCompression compression) {
  const vf::Image& image = frame();
  std::size_t bytes = 0;
  for (auto _ : state) bytes = vf::encodePng(image, compression, "bench").size();
  state.counters["bytes"] = static_cast<double>(bytes);
}

void EncodeFrame(benchmark::State& state) { encode(state, vf::PngCompression::fast); }
void EncodePicture(benchmark::State& state) { encode(state, vf::PngCompression::small); }

void LibpngDefault(benchmark::State& state) {
  const vf::Image& image = frame();
  png_alloc_size_t size = 0;
  for (auto _ : state) {
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = PNG_FORMAT_RGB;
    std::vector<std::uint8_t> out(static_cast<std::size_t>(image.width) * image.height * 4);
    size = out.size();
    if (!png_image_write_to_memory(&png, out.data(), &size, 0, image.rgb.data(), 0, nullptr))
      state.SkipWithError(png.message);
    png_image_free(&png);
  }
  state.counters["bytes"] = static_cast<double>(size);
}

BENCHMARK(EncodeFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(EncodePicture)->Unit(benchmark::kMillisecond);
BENCHMARK(LibpngDefault)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
