// voxfall diff EXPECTED ACTUAL: options into a DiffRequest; the comparison is
// render/run/diff_run.h. Exit code 0 when every frame is within tolerance, 1 when one is not
// (or is missing, or cannot be read), 2 for usage errors.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/diff_run.h"

namespace vf::cli {

void addDiffCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<DiffRequest>();
  const DiffTolerance defaults;
  CLI::App* sub = app.add_subcommand(
      "diff",
      "Compare two PNGs, or two folders of PNG frames by name: per-frame max channel "
      "difference, share of differing pixels, PSNR, SSIM; exit code 1 when over tolerance");
  sub->add_option("EXPECTED", o->expected, "the reference PNG or folder (e.g. goldens)")
      ->required()
      ->type_name("");
  sub->add_option("ACTUAL", o->actual, "the PNG or folder to check")->required()->type_name("");
  sub->add_option("--threshold,-t", o->tolerance.threshold,
                  "a pixel differs when one channel differs by more than T (0..255; default " +
                      std::to_string(defaults.threshold) + ")")
      ->check(CLI::Range(0, 255))
      ->type_name("T");
  char fraction[64];
  std::snprintf(fraction, sizeof fraction, "%g", defaults.maxFraction);
  sub->add_option("--max-fraction,-f", o->tolerance.maxFraction,
                  std::string("fail when more than this share of pixels differ (0..1; default ") +
                      fraction + ")")
      ->check(finiteNumberIn(0.0, 1.0))
      ->type_name("F");
  sub->add_option("--min-ssim", o->tolerance.minSsim,
                  "also fail when the mean SSIM (structural similarity, printed for every frame) "
                  "is under S (0..1; default: not judged)")
      ->check(finiteNumberIn(0.0, 1.0))
      ->type_name("S");
  sub->add_option("--out,-o", o->out,
                  "write the diff image (grey expected, red where over the threshold, blue "
                  "where under): a PNG file for two files, a folder for two folders")
      ->type_name("DIFF");
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runDiff(*o)); });
}

}  // namespace vf::cli
