// voxfall regress SUITE_DIR: golden-frame regression tests for voxfall and for users' scenes.
// Options into a RegressRequest, the run in render/run/regress_run.h (what a case checks, the
// reports it writes), the report lines to stdout as cases finish.
// Exit code 0 when everything passes, 1 when something failed (or bad input), 2 usage.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "render/cli/commands.h"
#include "render/run/regress_run.h"

namespace vf::cli {
namespace {

void print(const std::string& line) {
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
}

int runRegressCommand(const RegressRequest& request) {
  const std::string reportDir = reportFolder(request);
  RegressProgress progress;
  progress.onStart = [](const SuiteResult& s) { print(headerLine(s)); };
  progress.onCase = [&](const CaseResult& c) {
    for (const std::string& line : caseLines(c, reportDir)) print(line);
  };
  const SuiteResult result = runRegression(request, progress);
  print(closingLine(result));
  std::printf("report: %s/report.txt and %s/index.html (%.1f s; per case: %s/timings.txt)\n",
              reportDir.c_str(), reportDir.c_str(), result.seconds, reportDir.c_str());
  if (!request.junitFile.empty()) std::printf("JUnit XML: %s\n", request.junitFile.c_str());
  return result.passed() ? 0 : 1;
}

}  // namespace

void addRegressCommand(CLI::App& app, int& exitCode) {
  auto r = std::make_shared<RegressRequest>();
  CLI::App* sub = app.add_subcommand(
      "regress",
      "Golden-frame regression test: render the frames a suite lists, compare them and the "
      "trajectory checksums with the stored goldens, write a text, HTML and (optionally) JUnit "
      "report; --update rewrites goldens");
  sub->add_option("SUITE_DIR", r->suite,
                  "folder holding suite.toml and one folder of goldens per case")
      ->required()
      ->type_name("");
  sub->add_option("-o,--report", r->reportDir,
                  "folder for report.txt, index.html, timings.txt and the pictures of failing "
                  "frames (default: out/regress)")
      ->type_name("REPORT_DIR");
  sub->add_option("--junit", r->junitFile,
                  "also write the results as JUnit XML to this file, for CI systems")
      ->type_name("FILE");
  sub->add_flag("--update", r->update,
                "write the goldens (checksums and frames) that are missing or fail; keep those "
                "within tolerance. Look at the written PNGs before committing them");
  sub->add_option("--case", r->cases, "run only this case (repeat the option for more)")
      ->allow_extra_args(false)  // one name per --case: `--case a SUITE_DIR` keeps SUITE_DIR
      ->type_name("NAME");
  sub->add_option("-j,--jobs", r->jobs,
                  "render cases in this many processes at once (default 1); the reports are the "
                  "same bytes for any number")
      ->check(CLI::Range(1, 64))
      ->type_name("N");
  sub->add_option("--gl", r->gl, "OpenGL backend: osmesa (default) or egl (surfaceless)")
      ->check(CLI::IsMember({"osmesa", "egl"}))
      ->type_name("osmesa|egl");
  sub->add_option("--shaders", r->shaders, "folder of the GLSL sources (as for render)")
      ->type_name("DIR");
  sub->callback([r, &exitCode] { exitCode = runRegressCommand(*r); });
}

}  // namespace vf::cli
