// The voxfall command: subcommands register themselves (commands.h); main() owns the one place
// where errors become a message and an exit code, so every failure is reported exactly once:
//   0 success, 1 bad input or failed run, 2 usage error, 128 + the signal (130, 143) for a run
// stopped by SIGINT or SIGTERM, which keeps only whole outputs (render/run/stop_policy.h).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/run_report.h"
#include "sim/core/error.h"

namespace {

// The manual page that covers each command; installed beside the binary's share folder.
const char* manualPage(const std::string& command) {
  if (command == "render" || command == "export") return "rendering.md";
  if (command == "diff" || command == "regress") return "regression.md";
  if (command == "ensemble" || command == "ensemble-merge") return "ensembles.md";
  if (command == "figures" || command == "filmstrip" || command == "plot") return "paper.md";
  return "commands.md";
}

std::string manualNote(const std::string& page) {
  return "\nManual: docs/" + page + " in voxfall's source tree (installed as share/doc/voxfall/" +
         page + ").";
}

void pointToTheManual(CLI::App& app) {
  app.footer(manualNote("commands.md") +
             " Each command's --help names its page; README.md is the overview.");
  for (CLI::App* command : app.get_subcommands({})) {
    const std::string name = command->get_name();
    std::string note = manualNote(manualPage(name));
    if (name == "simulate") note += " What it writes: docs/output-formats.md.";
    command->footer(note);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "voxfall: rigid bodies with voxel sphere-tree collisions "
      "(Suzuki, Kubota & Ohtsubo 2003)",
      "voxfall"};
  app.set_version_flag("--version", std::string("voxfall ") + vf::voxfallVersion());
  app.require_subcommand(1);
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "voxfall: error: " + std::string(e.what()) + "\nRun with --help for more information.\n";
  });

  int exitCode = 0;
  vf::cli::addSimulateCommand(app, exitCode);
  vf::cli::addRenderCommand(app, exitCode);  // RENDER-COMMAND (render/cli/render_command.cpp)
  vf::cli::addExportCommand(app, exitCode);
  // Visual regression tests: render/run/diff_run.h and regress_run.h.
  vf::cli::addDiffCommand(app, exitCode);
  vf::cli::addRegressCommand(app, exitCode);
  // Figures for papers: render/run/figures_run.h (render/figures/).
  vf::cli::addFiguresCommand(app, exitCode);
  vf::cli::addFilmstripCommand(app, exitCode);
  vf::cli::addPlotCommand(app, exitCode);
  // Hazard ensembles: render/cli/ensemble_command.cpp (sim/ensemble/).
  vf::cli::addEnsembleCommand(app, exitCode);
  vf::cli::addEnsembleMergeCommand(app, exitCode);
  pointToTheManual(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version arrive here too, with exit code 0.
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const std::exception& e) {  // vf::InputError included: what() is "where: message"
    std::fprintf(stderr, "voxfall: error: %s\n", e.what());
    return 1;
  }
  return exitCode;
}
