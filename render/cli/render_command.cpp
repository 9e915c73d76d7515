// voxfall render INPUT: options into a RenderRequest; the run (simulation, drawing, output, stop
// policy) is render/run/render_run.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/render_run.h"

namespace vf::cli {

void addRenderCommand(CLI::App& app, int& exitCode) {
  // Owned by the callback: CLI11 fills it during parse, after this function has returned.
  auto o = std::make_shared<RenderRequest>();
  CLI::App* sub = app.add_subcommand(
      "render",
      "Simulate a scene (or read a bake) and render its frames to an MP4 or a PNG sequence");
  sub->add_option("INPUT", o->input, "scene file (TOML) or bake (voxfall simulate --bake)")
      ->required()
      ->type_name("");
  sub->add_option("-o,--output", o->output,
                  "OUT.mp4 (H.264), or a PNG pattern whose '#' run becomes the frame number, "
                  "e.g. out/cubes/frame_####.png (default: out/<scene name>.mp4)")
      ->type_name("OUT");
  sub->add_option("--frames", o->frames,
                  "frames to draw, A:B inclusive (30:30 is one frame; the simulation still "
                  "starts at t = 0)")
      ->type_name("A:B");
  addSizeOption(*sub, o->drawing.size);
  sub->add_option("--fps", o->drawing.fps, "frames per second (overrides [simulation] fps)")
      ->check(finiteNumberIn(0.001, 1000.0))
      ->type_name("N");
  addSpeedOption(*sub, o->drawing.speed);
  addFrameLookOptions(*sub, o->drawing.alpha, o->drawing.overlay);
  addPhysicsOptions(*sub, o->overrides, " (scenes only)");
  addThreadsOption(*sub, o->overrides, " (scenes only)");
  sub->add_option("--crf", o->drawing.crf, "H.264 quality, 0..51, lower is better (default: 18)")
      ->check(CLI::Range(0, 51))
      ->type_name("N");
  sub->add_option("--gl", o->gl, "OpenGL backend: osmesa (default) or egl (surfaceless)")
      ->check(CLI::IsMember({"osmesa", "egl"}))
      ->type_name("osmesa|egl");
  sub->add_option("--shaders", o->shaders,
                  "folder of the GLSL sources (default: next to the binary, else the source "
                  "tree's shaders/)")
      ->type_name("DIR");
  sub->add_option("--camera", o->drawing.camera,
                  "which of the scene's cameras to use: a [cameras.NAME] table, or 'camera' for "
                  "[camera] (the default)")
      ->type_name("NAME");
  sub->add_flag("--quiet,-q", o->quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->overwrite, o->neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runRender(*o)); });
}

}  // namespace vf::cli
