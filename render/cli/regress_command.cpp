// voxfall regress SUITE_DIR: golden-frame regression tests for voxfall and for users' scenes.
//
// A suite is a folder: SUITE_DIR/suite.toml lists cases (a scene, the frames to check, a size,
// optionally a tolerance), and SUITE_DIR/<case name>/ holds the goldens: frame_NNNN.png per
// checked frame and checksum.txt, the trajectory checksum of the run. For each case the scene is
// simulated and the frames drawn in-process, exactly as `voxfall render --frames k:k` draws them
// (renderSceneFrames); then
//   - the checksum must equal the golden one: the states are bit-identical by design, so any
//     difference means the physics changed, even when the pixels barely move;
//   - each frame must be within the case's tolerance of its golden (image_diff.h).
// Failures are listed on stdout and in REPORT_DIR/report.txt, and each failing frame gets
// REPORT_DIR/<case>/frame_NNNN_compare.png: expected | actual | diff side by side.
// Exit code 0 when everything passes, 1 when something failed (or bad input), 2 usage.
//
// A case with `runs = K` checks an ensemble scene instead: its first K realisations, each
// stepped alone as `voxfall ensemble` steps it, drawn together from their bake exactly as
// `voxfall ensemble --video-runs K` writes ensemble_subset.bake and `voxfall render` draws it.
// Its checksum.txt holds K words, runs.csv's checksums of realisations 0..K-1, and a failure
// names the realisations whose states changed.
//
// --update writes the goldens that are missing or fail (each through a temporary file and a
// rename) and keeps the ones within tolerance, so that a review of the change (`git diff`,
// looking at the PNGs) shows only what really changed. To regenerate a case from scratch,
// delete its folder and run --update.
//
// suite.toml is read by toml++ (render/regress_suite.h), as the golden tests read it.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "render/cli/commands.h"
#include "render/cli/run_output.h"
#include "render/gl/gl_context.h"
#include "render/gl/shader_program.h"
#include "render/output/image_diff.h"
#include "render/output/png_writer.h"
#include "render/regress_suite.h"
#include "render/scene_playback.h"
#include "sim/core/error.h"
#include "sim/ensemble/ensemble.h"
#include "sim/ensemble/ensemble_bake.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"

namespace vf::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSuiteFile = "suite.toml";
constexpr const char* kGoldenPattern = "frame_####.png";
constexpr const char* kChecksumFile = "checksum.txt";

// --- the run --------------------------------------------------------------------------------

struct RegressOptions {
  std::string suite;
  std::string report;  // "": out/regress
  bool update = false;
  std::vector<std::string> only;  // --case NAME: run only these
  std::string gl = "osmesa";
  std::string shaders;
};

// Lines go to stdout as they come and into report.txt at the end.
class ReportLog {
 public:
  void line(const std::string& text) {
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
    text_ += text + "\n";
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

// checksum.txt's words joined by single spaces: one for a scene, one per realisation for an
// ensemble case; "" when the file is missing.
std::string readChecksum(const fs::path& path) {
  std::ifstream in(path);
  std::string all, word;
  while (in >> word) all += (all.empty() ? "" : " ") + word;
  return all;
}

std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// checksum.txt through a temporary file and a rename (OutputFile), like every other output.
void writeChecksum(const fs::path& path, const std::string& checksum) {
  OutputFile file(path.string(), replaceOutputs());
  std::fprintf(file.stream(), "%s\n", checksum.c_str());
  file.commit();
}

// Report files of an earlier run for this case, so a frame that passes now leaves no picture.
void removeOldReportImages(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  std::vector<fs::path> old;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.starts_with("frame_") &&
        (name.ends_with("_compare.png") || name.ends_with("_actual.png")))
      old.push_back(it->path());
  }
  for (const fs::path& p : old) fs::remove(p, ec);
}

struct Counts {
  int framesPassed = 0;
  int framesFailed = 0;
  int goldensWritten = 0;  // --update: frames and checksums
  int checksumsFailed = 0;
  int casesFailed = 0;  // cases that could not run
};

// What a case made: its frames and its trajectory checksum.
struct CaseRun {
  std::vector<Image> images;
  // A scene: the run's checksum (16 hex digits). An ensemble case: one per realisation, in
  // index order, separated by spaces: runs.csv's `checksum` column of `voxfall ensemble`.
  std::string checksum;
  int width = 0, height = 0;
  std::string what;  // "" or ", 3 ensemble realisations"
};

CaseRun runCaseFrames(const SuiteCase& c, gl::Context& context, const std::string& shaderDir) {
  SceneSpec spec = loadScene(c.scene);
  if (c.width) spec.output.width = *c.width;
  if (c.height) spec.output.height = *c.height;
  CaseRun run;
  run.width = spec.output.width;
  run.height = spec.output.height;
  if (!c.runs) {
    RenderedFrames rendered = renderSceneFrames(spec, c.frames, context, shaderDir);
    run.images = std::move(rendered.images);
    run.checksum = rendered.summary.checksumHex();
    return run;
  }
  // An ensemble's first K realisations, each stepped alone (Ensemble::run's steps) and drawn
  // together from their bake, as `voxfall ensemble --runs N --video-runs K` (N >= K) writes
  // ensemble_subset.bake and `voxfall render` draws it.
  if (!spec.ensemble)
    throw InputError(c.where, "'runs' is for a scene with an [ensemble] table, and " + c.scene +
                                  " has none (leave 'runs' out to draw the scene itself)");
  const Ensemble ensemble(spec);
  std::vector<std::int64_t> indices(static_cast<std::size_t>(*c.runs));
  std::iota(indices.begin(), indices.end(), std::int64_t{0});
  std::vector<std::uint64_t> checksums;
  auto bake = std::make_shared<const Bake>(
      ensembleBake(ensemble, spec.ensemble->seed, indices, &checksums));
  run.images = renderBakeFrames(bake, c.where, c.frames, run.width, run.height, context, shaderDir);
  for (const std::uint64_t sum : checksums)
    run.checksum += (run.checksum.empty() ? "" : " ") + checksumHex(sum);
  run.what = ", " + std::to_string(*c.runs) + " ensemble realisation" + (*c.runs == 1 ? "" : "s");
  return run;
}

// For a changed ensemble checksum: which realisations changed ("" when the counts differ).
std::string changedRealisations(const std::string& actual, const std::string& golden) {
  const std::vector<std::string> a = words(actual), g = words(golden);
  if (a.size() < 2 || a.size() != g.size()) return "";
  std::string list;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != g[i]) list += (list.empty() ? "" : ", ") + std::to_string(i);
  return " (realisations " + list + ")";
}

void runCase(const SuiteCase& c, const fs::path& suiteDir, const fs::path& reportDir, bool update,
             gl::Context& context, const std::string& shaderDir, ReportLog& log, Counts& counts) {
  const auto start = std::chrono::steady_clock::now();
  const CaseRun rendered = runCaseFrames(c, context, shaderDir);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const fs::path goldenDir = suiteDir / c.name;
  const fs::path caseReport = reportDir / c.name;
  std::error_code ec;
  removeOldReportImages(caseReport);
  if (update) {
    fs::create_directories(goldenDir, ec);
    if (ec)
      throw InputError(goldenDir.string(), "cannot create the golden folder: " + ec.message());
  }
  char head[200];
  std::snprintf(head, sizeof head, "%s: %zu frames at %dx%d%s in %.1f s", c.name.c_str(),
                c.frames.size(), rendered.width, rendered.height, rendered.what.c_str(), seconds);
  log.line(head);

  // The trajectory checksum (one per realisation for an ensemble case).
  const std::string& checksum = rendered.checksum;
  const fs::path checksumPath = goldenDir / kChecksumFile;
  const std::string golden = readChecksum(checksumPath);
  if (golden == checksum) {
    log.line("  checksum " + checksum + ": ok");
  } else if (update) {
    writeChecksum(checksumPath, checksum);
    log.line("  checksum " + checksum + ": WRITTEN" +
             (golden.empty() ? std::string(" (new)") : " (was " + golden + ")"));
    ++counts.goldensWritten;
  } else if (golden.empty()) {
    log.line("  checksum " + checksum + ": MISSING golden " + checksumPath.string() +
             " (run with --update to create it)");
    ++counts.checksumsFailed;
  } else {
    log.line("  checksum " + checksum + ": FAIL, golden " + golden + ": the physics changed" +
             changedRealisations(checksum, golden) +
             " (the simulated states are not bit-identical; the frames "
             "below show whether it is visible)");
    ++counts.checksumsFailed;
  }

  // The frames.
  for (std::size_t i = 0; i < c.frames.size(); ++i) {
    const Image& actual = rendered.images[i];
    const std::string file = expandFramePattern(kGoldenPattern, c.frames[i]);
    const fs::path goldenPath = goldenDir / file;
    const std::string label = "  " + file + ": ";
    std::optional<Image> expected;
    std::string readError;
    if (fs::exists(goldenPath, ec)) {
      try {
        expected = readPng(goldenPath.string());
      } catch (const InputError& e) {
        readError = e.what();
      }
    }
    if (expected) {
      const DiffMetrics m = compareImages(*expected, actual, c.tolerance.threshold);
      const std::string numbers = describe(m, *expected, actual);
      if (withinTolerance(m, c.tolerance)) {
        log.line(label + "ok    " + numbers);
        ++counts.framesPassed;
        continue;
      }
      if (update) {
        writePng(goldenPath.string(), actual);
        log.line(label + "WRITTEN (was: " + numbers + ")");
        ++counts.goldensWritten;
        continue;
      }
      fs::create_directories(caseReport, ec);
      const fs::path picture = caseReport / (fs::path(file).stem().string() + "_compare.png");
      writePng(picture.string(),
               sideBySide(*expected, actual, diffImage(*expected, actual, c.tolerance.threshold)));
      log.line(label + "FAIL  " + numbers + " -> " + picture.string());
      ++counts.framesFailed;
      continue;
    }
    if (update) {
      writePng(goldenPath.string(), actual);
      log.line(label + "WRITTEN (new)");
      ++counts.goldensWritten;
      continue;
    }
    fs::create_directories(caseReport, ec);
    const fs::path picture = caseReport / (fs::path(file).stem().string() + "_actual.png");
    writePng(picture.string(), actual);
    log.line(label +
             (readError.empty()
                  ? "MISSING golden " + goldenPath.string() + " (run with --update to create it)"
                  : "FAIL  " + readError) +
             " -> " + picture.string());
    ++counts.framesFailed;
  }

  // Goldens no case lists any more: harmless, but worth a look.
  const std::set<int> listed(c.frames.begin(), c.frames.end());
  std::vector<std::string> stale;
  for (fs::directory_iterator it(goldenDir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    int k = -1;
    char tail = 0;
    if (std::sscanf(name.c_str(), "frame_%d.pn%c", &k, &tail) == 2 && tail == 'g' &&
        !listed.count(k))
      stale.push_back(name);
  }
  std::sort(stale.begin(), stale.end());
  for (const std::string& name : stale)
    log.line("  " + name + ": not in " + std::string(kSuiteFile) + " (an old golden? delete it)");
}

int runRegress(const RegressOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path suiteDir(o.suite);
  std::error_code ec;
  if (!fs::is_directory(suiteDir, ec))
    throw InputError(o.suite, "not a folder (a suite is a folder holding suite.toml)");
  const Suite suite = readSuite((suiteDir / kSuiteFile).string());
  for (const std::string& name : o.only) {
    if (std::none_of(suite.cases.begin(), suite.cases.end(),
                     [&](const SuiteCase& c) { return c.name == name; }))
      throw InputError(o.suite, "--case " + name + ": no case of that name in suite.toml");
  }

  const fs::path reportDir = o.report.empty() ? fs::path("out/regress") : fs::path(o.report);
  fs::create_directories(reportDir, ec);
  if (ec) throw InputError(reportDir.string(), "cannot create the report folder: " + ec.message());
  // GL and shaders once for the whole suite: a missing library fails here, in seconds.
  auto context = gl::createContext(gl::parseBackend(o.gl));
  const std::string shaderDir = gl::findShaderDir(o.shaders);

  ReportLog log;
  log.line(std::string("voxfall regress ") + suiteDir.string() + (o.update ? " --update" : "") +
           " (" + context->description() + ")");
  Counts counts;
  int casesRun = 0;
  for (const SuiteCase& c : suite.cases) {
    if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), c.name) == o.only.end())
      continue;
    ++casesRun;
    try {
      runCase(c, suite.dir, reportDir, o.update, *context, shaderDir, log, counts);
    } catch (const std::exception& e) {
      // A broken scene fails its case; the other cases still run.
      log.line(c.name + " (" + c.where + "): ERROR " + e.what());
      ++counts.casesFailed;
    }
  }

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool passed =
      counts.framesFailed == 0 && counts.checksumsFailed == 0 && counts.casesFailed == 0;
  const auto plural = [](int n, const char* word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
  };
  const std::string notRun =
      counts.casesFailed ? ", " + plural(counts.casesFailed, "case") + " could not run" : "";
  const std::string cases = plural(casesRun, "case");
  char tail[320];
  if (o.update) {
    std::snprintf(
        tail, sizeof tail,
        "%s: %s, %d goldens written, %d frames kept (within tolerance)%s, in "
        "%.1f s%s",
        passed ? "UPDATED" : "FAIL", cases.c_str(), counts.goldensWritten, counts.framesPassed,
        notRun.c_str(), seconds,
        counts.goldensWritten > 0 ? ". Look at the written PNGs before committing them." : "");
  } else {
    std::snprintf(tail, sizeof tail,
                  "%s: %s, %d of %d frames passed, %d checksums changed or missing%s, in "
                  "%.1f s",
                  passed ? "PASS" : "FAIL", cases.c_str(), counts.framesPassed,
                  counts.framesPassed + counts.framesFailed, counts.checksumsFailed, notRun.c_str(),
                  seconds);
  }
  log.line(tail);
  const fs::path reportFile = reportDir / "report.txt";
  {
    OutputFile report(reportFile.string(), replaceOutputs());
    std::fputs(log.text().c_str(), report.stream());
    report.commit();
  }
  std::printf("report: %s\n", reportFile.string().c_str());
  return passed ? 0 : 1;
}

}  // namespace

void addRegressCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<RegressOptions>();
  CLI::App* sub = app.add_subcommand(
      "regress",
      "Golden-frame regression test: render the frames a suite lists, compare them and the "
      "trajectory checksums with the stored goldens, write a report; --update rewrites goldens");
  sub->add_option("SUITE_DIR", o->suite,
                  "folder holding suite.toml and one folder of goldens per case")
      ->required()
      ->type_name("");
  sub->add_option("-o,--report", o->report,
                  "folder for report.txt and the expected|actual|diff pictures of failing "
                  "frames (default: out/regress)")
      ->type_name("REPORT_DIR");
  sub->add_flag("--update", o->update,
                "write the goldens (checksums and frames) that are missing or fail; keep those "
                "within tolerance. Look at the written PNGs before committing them");
  sub->add_option("--case", o->only, "run only this case (repeat the option for more)")
      ->allow_extra_args(false)  // one name per --case: `--case a SUITE_DIR` keeps SUITE_DIR
      ->type_name("NAME");
  sub->add_option("--gl", o->gl, "OpenGL backend: osmesa (default) or egl (surfaceless)")
      ->check(CLI::IsMember({"osmesa", "egl"}))
      ->type_name("osmesa|egl");
  sub->add_option("--shaders", o->shaders, "folder of the GLSL sources (as for render)")
      ->type_name("DIR");
  sub->callback([o, &exitCode] { exitCode = runRegress(*o); });
}

}  // namespace vf::cli
