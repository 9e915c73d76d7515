#include "render/run/regress_case.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>
#include <vector>

#include "render/output/compare_image.h"
#include "render/output/image_diff.h"
#include "render/output/output_file.h"
#include "render/output/png_writer.h"
#include "render/scene_playback.h"
#include "sim/core/error.h"
#include "sim/ensemble/ensemble.h"
#include "sim/ensemble/ensemble_bake.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

constexpr const char* kGoldenPattern = "frame_####.png";
constexpr const char* kChecksumFile = "checksum.txt";

// checksum.txt's words joined by single spaces; "" when the file is missing.
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

void writeChecksum(const fs::path& path, const std::string& checksum) {
  OutputFile file(path.string(), replaceOutputs());
  std::fprintf(file.stream(), "%s\n", checksum.c_str());
  file.commit();
}

// Pictures of an earlier run for this case, so a frame that passes now leaves none behind.
void removeOldReportImages(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  std::vector<fs::path> old;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.starts_with("frame_")) continue;
    for (const char* tail : {"_compare.png", "_actual.png", "_expected.png", "_diff.png"})
      if (name.ends_with(tail)) old.push_back(it->path());
  }
  for (const fs::path& p : old) fs::remove(p, ec);
}

// What a case made: its frames and its trajectory checksum (one word per realisation for an
// ensemble case, runs.csv's `checksum` column of `voxfall ensemble`).
struct CaseRun {
  std::vector<Image> images;
  std::string checksum;
  int width = 0, height = 0;
  std::string what;  // "" or ", 3 ensemble realisations"
};

CaseRun drawEnsembleCase(const SuiteCase& c, const SceneSpec& spec, CaseRun run,
                         gl::Context& context, const std::string& shaderDir) {
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
  for (const std::uint64_t sum : checksums) {
    if (!run.checksum.empty()) run.checksum += ' ';
    run.checksum += checksumHex(sum);
  }
  run.what = ", " + std::to_string(*c.runs) + " ensemble realisation" + (*c.runs == 1 ? "" : "s");
  return run;
}

CaseRun drawCase(const SuiteCase& c, gl::Context& context, const std::string& shaderDir) {
  SceneSpec spec = loadScene(c.scene);
  if (c.width) spec.output.width = *c.width;
  if (c.height) spec.output.height = *c.height;
  CaseRun run;
  run.width = spec.output.width;
  run.height = spec.output.height;
  for (const PixelRect& r : c.mask)
    if (r.x + r.width > run.width || r.y + r.height > run.height)
      throw InputError(c.maskWhere, "mask rectangle [" + std::to_string(r.x) + ", " +
                                        std::to_string(r.y) + ", " + std::to_string(r.width) +
                                        ", " + std::to_string(r.height) + "] reaches outside the " +
                                        std::to_string(run.width) + "x" +
                                        std::to_string(run.height) + " frame");
  if (c.runs) return drawEnsembleCase(c, spec, std::move(run), context, shaderDir);
  RenderedFrames rendered = renderSceneFrames(spec, c.frames, context, shaderDir);
  run.images = std::move(rendered.images);
  run.checksum = rendered.summary.checksumHex();
  return run;
}

// Which realisations of an ensemble case changed ("" when the counts differ).
std::string changedRealisations(const std::string& actual, const std::string& golden) {
  const std::vector<std::string> a = words(actual), g = words(golden);
  if (a.size() < 2 || a.size() != g.size()) return "";
  std::string list;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != g[i]) list += (list.empty() ? "" : ", ") + std::to_string(i);
  return " (realisations " + list + ")";
}

void judgeChecksum(CaseResult& r, const fs::path& goldenDir, bool update) {
  const fs::path path = goldenDir / kChecksumFile;
  r.checksumPath = path.string();
  r.goldenChecksum = readChecksum(path);
  if (r.goldenChecksum == r.checksum) {
    r.checksumStatus = ChecksumStatus::kOk;
  } else if (update) {
    writeChecksum(path, r.checksum);
    r.checksumStatus =
        r.goldenChecksum.empty() ? ChecksumStatus::kWrittenNew : ChecksumStatus::kWritten;
  } else {
    r.checksumStatus = r.goldenChecksum.empty() ? ChecksumStatus::kMissing : ChecksumStatus::kFail;
    r.changedRealisations = changedRealisations(r.checksum, r.goldenChecksum);
  }
}

// A frame outside tolerance: expected, actual and diff for the HTML report, and the labelled
// picture with the crop for people at a terminal.
void writeFailurePictures(FrameResult& f, const SuiteCase& c, const Image& expected,
                          const Image& actual, const fs::path& reportDir) {
  const fs::path folder = reportDir / c.name;
  fs::create_directories(folder);
  const std::string stem = c.name + "/" + fs::path(f.file).stem().string();
  const Image diff = diffImage(expected, actual, c.tolerance.threshold, c.mask);
  f.crop = changedRegion(expected, actual, c.tolerance.threshold, c.mask);
  f.expectedImage = stem + "_expected.png";
  f.actualImage = stem + "_actual.png";
  f.diffImage = stem + "_diff.png";
  f.compareImage = stem + "_compare.png";
  writePng((reportDir / f.expectedImage).string(), expected);
  writePng((reportDir / f.actualImage).string(), actual);
  writePng((reportDir / f.diffImage).string(), diff);
  writePng((reportDir / f.compareImage).string(), comparePicture(expected, actual, diff, f.crop));
}

std::optional<Image> readGolden(const fs::path& path, FrameResult& f) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  try {
    return readPng(path.string());
  } catch (const InputError& e) {
    f.detail = e.what();
    return std::nullopt;
  }
}

FrameResult judgeFrame(const SuiteCase& c, int frame, const Image& actual,
                       const fs::path& goldenDir, const fs::path& reportDir, bool update) {
  FrameResult f;
  f.frame = frame;
  f.file = expandFramePattern(kGoldenPattern, frame);
  const fs::path goldenPath = goldenDir / f.file;
  if (std::optional<Image> expected = readGolden(goldenPath, f)) {
    f.compared = true;
    f.metrics = compareImages(*expected, actual, c.tolerance.threshold, c.mask);
    f.detail = describe(f.metrics, *expected, actual);
    if (withinTolerance(f.metrics, c.tolerance)) {
      f.status = FrameStatus::kOk;
    } else if (update) {
      writePng(goldenPath.string(), actual);
      f.status = FrameStatus::kWritten;
    } else {
      f.status = FrameStatus::kFail;
      writeFailurePictures(f, c, *expected, actual, reportDir);
    }
    return f;
  }
  if (update) {
    writePng(goldenPath.string(), actual);
    f.status = FrameStatus::kWrittenNew;
    return f;
  }
  f.status = f.detail.empty() ? FrameStatus::kMissing : FrameStatus::kUnreadable;
  if (f.detail.empty())
    f.detail = "MISSING golden " + goldenPath.string() + " (run with --update to create it)";
  fs::create_directories(reportDir / c.name);
  f.actualImage = c.name + "/" + fs::path(f.file).stem().string() + "_actual.png";
  writePng((reportDir / f.actualImage).string(), actual);
  return f;
}

// Goldens no frame of the case lists any more: harmless, but worth a look.
std::vector<std::string> staleGoldens(const SuiteCase& c, const fs::path& goldenDir) {
  const std::set<int> listed(c.frames.begin(), c.frames.end());
  std::vector<std::string> stale;
  std::error_code ec;
  for (fs::directory_iterator it(goldenDir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    int k = -1;
    char tail = 0;
    if (std::sscanf(name.c_str(), "frame_%d.pn%c", &k, &tail) == 2 && tail == 'g' &&
        !listed.count(k))
      stale.push_back(name);
  }
  std::sort(stale.begin(), stale.end());
  return stale;
}

}  // namespace

CaseResult runRegressionCase(const SuiteCase& c, const fs::path& suiteDir,
                             const fs::path& reportDir, bool update, gl::Context& context,
                             const std::string& shaderDir) {
  const auto start = std::chrono::steady_clock::now();
  const CaseRun run = drawCase(c, context, shaderDir);
  CaseResult r;
  r.name = c.name;
  r.where = c.where;
  r.width = run.width;
  r.height = run.height;
  r.what = run.what;
  r.checksum = run.checksum;
  const fs::path goldenDir = suiteDir / c.name;
  removeOldReportImages(reportDir / c.name);
  if (update) {
    std::error_code ec;
    fs::create_directories(goldenDir, ec);
    if (ec)
      throw InputError(goldenDir.string(), "cannot create the golden folder: " + ec.message());
  }
  judgeChecksum(r, goldenDir, update);
  for (std::size_t i = 0; i < c.frames.size(); ++i)
    r.frames.push_back(judgeFrame(c, c.frames[i], run.images[i], goldenDir, reportDir, update));
  r.stale = staleGoldens(c, goldenDir);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace vf
