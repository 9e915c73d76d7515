// The voxfall command's subcommands. Each adds itself to the CLI11 app and returns the
// process exit code through the callback's `exitCode`.
#pragma once

namespace CLI {
class App;
}

namespace vf::cli {

// voxfall simulate SCENE [--csv FILE] [--summary FILE] [--level N] [--step S|auto|clearance]
// [--quiet]
void addSimulateCommand(CLI::App& app, int& exitCode);
// voxfall render SCENE [-o OUT] [--frames A:B] [--size WxH] [--fps N] [--level N] [--crf N]
void addRenderCommand(CLI::App& app, int& exitCode);
// voxfall export SCENE|BAKE [-o FILE.glb] [--fps N] [-y|-n]
void addExportCommand(CLI::App& app, int& exitCode);
// voxfall diff EXPECTED ACTUAL [--threshold T] [--max-fraction F] [--out DIFF]
void addDiffCommand(CLI::App& app, int& exitCode);
// voxfall regress SUITE_DIR [-o REPORT_DIR] [--update]
void addRegressCommand(CLI::App& app, int& exitCode);
// voxfall figures [NAME...] [-o DIR] [--quick]
void addFiguresCommand(CLI::App& app, int& exitCode);
// voxfall filmstrip SCENE --times T,T,... [-o FILE.png] [--size WxH] [--columns N]
void addFilmstripCommand(CLI::App& app, int& exitCode);
// voxfall plot RUN.csv [--scene SCENE] [-o DIR]
void addPlotCommand(CLI::App& app, int& exitCode);
// voxfall ensemble SCENE --runs N [--seed S] [--jobs J] [--only i] [-o DIR] [--converge]
// [--resume] [--shard i/n]
void addEnsembleCommand(CLI::App& app, int& exitCode);
// voxfall ensemble-merge DIR... -o OUT [--converge] [--maps] [--video-runs K]
void addEnsembleMergeCommand(CLI::App& app, int& exitCode);

}  // namespace vf::cli
