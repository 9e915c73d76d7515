// voxfall filmstrip SCENE --times T,T,...: options into a FilmstripRequest; the run is
// render/run/filmstrip_run.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/filmstrip_run.h"

namespace vf::cli {

void addFilmstripCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<FilmstripRequest>();
  CLI::App* sub = app.add_subcommand(
      "filmstrip", "Frames of a scene at chosen times side by side in one PNG, labelled");
  sub->add_option("SCENE", o->scene, "scene file (TOML)")->required()->type_name("");
  sub->add_option("--times", o->times, "times in seconds, comma-separated, e.g. 0.5,1,2,4")
      ->required()
      ->type_name("T,T,...");
  sub->add_option("-o,--output", o->output, "PNG file (default: out/<scene>_filmstrip.png)")
      ->type_name("FILE.png");
  addSizeOption(*sub, o->size);
  sub->add_option("--columns", o->columns, "frames per row (default: all in one row)")
      ->check(CLI::Range(1, 100))
      ->type_name("N");
  addPhysicsOptions(*sub, o->overrides);
  addOverwriteFlags(*sub, o->overwrite, o->neverOverwrite);
  sub->add_option("--gl", o->gl, "OpenGL backend: osmesa (default) or egl (surfaceless)")
      ->check(CLI::IsMember({"osmesa", "egl"}));
  sub->add_option("--shaders", o->shaders, "folder of the GLSL shaders")->type_name("DIR");
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runFilmstrip(*o)); });
}

}  // namespace vf::cli
