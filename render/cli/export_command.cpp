// voxfall export SCENE|BAKE -o FILE.glb: options into an ExportRequest; the export is
// render/run/export_run.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/export_run.h"

namespace vf::cli {

void addExportCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<ExportRequest>();
  CLI::App* sub = app.add_subcommand(
      "export",
      "Write a scene's or a bake's animation as glTF 2.0 (.glb): meshes, one animated "
      "node per body, a key per frame");
  sub->add_option("INPUT", o->input, "scene file (TOML) or bake")->required()->type_name("");
  sub->add_option("-o,--output", o->output, "FILE.glb (default: out/<scene name>.glb)")
      ->type_name("FILE");
  sub->add_option("--fps", o->fps, "key frames per second (overrides [simulation] fps)")
      ->check(finiteNumberIn(0.001, 1000.0))
      ->type_name("N");
  addSpeedOption(*sub, o->speed);
  addPhysicsOptions(*sub, o->overrides, " (scenes only)");
  addThreadsOption(*sub, o->overrides, " (scenes only)");
  sub->add_flag("--quiet,-q", o->quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->overwrite, o->neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runExport(*o)); });
}

}  // namespace vf::cli
