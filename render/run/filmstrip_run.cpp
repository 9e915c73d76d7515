#include "render/run/filmstrip_run.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "render/figures/filmstrip.h"
#include "render/gl/gl_context.h"
#include "render/gl/shader_program.h"
#include "render/output/output_file.h"
#include "render/output/png_writer.h"
#include "render/run/run_input.h"
#include "render/scene_playback.h"
#include "sim/core/error.h"
#include "sim/scene/scene.h"
#include "sim/shape/sphere_tree.h"

namespace vf {
namespace {

// "0.5,1,2,4" -> seconds; InputError for anything that is not a list of times >= 0.
std::vector<double> parseTimes(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double t = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(t) || t < 0)
      throw InputError("--times", "'" + item + "' is not a time in seconds >= 0");
    out.push_back(t);
  }
  if (out.empty()) throw InputError("--times", "give at least one time, e.g. 0.5,1,2,4");
  return out;
}

}  // namespace

RunStatus runFilmstrip(const FilmstripRequest& o) {
  RunInput input = loadRunInput(o.scene, o.overrides);
  if (input.bake)
    throw InputError(o.scene,
                     "filmstrip draws a scene; render a bake's frames with voxfall render");
  SceneSpec& spec = input.spec;
  if (o.size) std::tie(spec.output.width, spec.output.height) = *o.size;
  // A filmstrip picks its frames by time and labels them itself, on an opaque picture.
  spec.output.speed = 1;
  spec.output.alpha = spec.output.overlayTime = spec.output.overlayScale = false;
  const std::vector<double> times = parseTimes(o.times);
  const int last = Recorder::frameCountFor(spec.fps, spec.duration) - 1;
  std::vector<int> frames;
  std::vector<std::string> labels;
  for (double t : times) {
    const int k = static_cast<int>(std::lround(t * spec.fps));
    if (k > last)
      throw InputError("--times", "time " + fig::timeLabel(t).substr(4) +
                                      " is after the scene's end (" +
                                      fig::timeLabel(last / spec.fps).substr(4) + ")");
    frames.push_back(k);
    labels.push_back(fig::timeLabel(k / spec.fps));
  }
  const std::string path = o.output.empty() ? "out/" + spec.name + "_filmstrip.png" : o.output;
  // An existing or unwritable destination fails before any simulation.
  OutputFile out(path, runOutputRules(spec, o.scene, o.overwrite, o.neverOverwrite));

  auto context = gl::createContext(gl::parseBackend(o.gl));
  const RenderedFrames rendered =
      renderSceneFrames(spec, frames, *context, gl::findShaderDir(o.shaders));
  const int columns = o.columns > 0 ? o.columns : static_cast<int>(frames.size());
  const Image strip = fig::composeFilmstrip(rendered.images, labels, columns);
  out.closeStream();
  writePng(out.tempPath(), strip);
  out.commit();
  std::printf("%s: %zu frames -> %s (%dx%d)\n", spec.name.c_str(), frames.size(), path.c_str(),
              strip.width, strip.height);
  return RunStatus::done();
}

}  // namespace vf
