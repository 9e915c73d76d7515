#include "render/run/diff_run.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "render/output/image_diff.h"
#include "render/output/output_file.h"
#include "render/output/png_writer.h"
#include "sim/core/error.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

bool isPng(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png";
}

// The PNG file names in a folder, sorted (frame_0000.png before frame_0010.png).
std::vector<std::string> pngNames(const fs::path& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file(ec) && isPng(it->path())) names.push_back(it->path().filename());
  }
  if (ec) throw InputError(folder.string(), "cannot list the folder: " + ec.message());
  std::sort(names.begin(), names.end());
  return names;
}

// Diff images replace earlier ones, as reports do, but never one of the two compared images.
OutputRules diffImageRules(const fs::path& expectedPath, const fs::path& actualPath) {
  OutputRules rules = replaceOutputs();
  rules.inputs = {expectedPath.string(), actualPath.string()};
  return rules;
}

// Compares one pair, prints its line, writes its diff image when `diffPath` is given.
// Returns true when within tolerance.
bool comparePair(const std::string& label, const fs::path& expectedPath, const fs::path& actualPath,
                 const DiffTolerance& tolerance, const std::string& diffPath) {
  const OutputRules rules = diffImageRules(expectedPath, actualPath);
  if (!diffPath.empty()) checkOutputPath(diffPath, rules);  // before anything is printed
  const Image expected = readPng(expectedPath.string());
  const Image actual = readPng(actualPath.string());
  const DiffMetrics m = compareImages(expected, actual, tolerance.threshold);
  const bool ok = withinTolerance(m, tolerance);
  std::printf("%s: %-4s  %s\n", label.c_str(), ok ? "ok" : "FAIL",
              describe(m, expected, actual).c_str());
  if (!diffPath.empty())
    writePng(diffPath, diffImage(expected, actual, tolerance.threshold), rules);
  return ok;
}

std::string toleranceText(const DiffTolerance& t) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "a pixel differs when a channel differs by more than %d/255; at most %g%% of "
                "pixels may differ",
                t.threshold, 100 * t.maxFraction);
  std::string text = buf;
  if (t.minSsim) {
    std::snprintf(buf, sizeof buf, "; SSIM at least %g", *t.minSsim);
    text += buf;
  }
  return text;
}

// The folder of the diff images. They take the frames' names: in either compared folder they
// would replace the frames themselves.
void makeDiffFolder(const DiffRequest& o) {
  std::error_code ec;
  for (const std::string& compared : {o.expected, o.actual})
    if (fs::equivalent(o.out, compared, ec))
      throw InputError(o.out, "is the folder of the compared frames (" + compared +
                                  "); the diff images would overwrite them: give another folder");
  fs::create_directories(o.out, ec);
  if (ec) throw InputError(o.out, "cannot create the diff folder: " + ec.message());
}

RunStatus verdict(bool ok) { return ok ? RunStatus::done() : RunStatus::failed(); }

RunStatus diffFiles(const DiffRequest& o) {
  const bool ok =
      comparePair(fs::path(o.actual).filename().string(), o.expected, o.actual, o.tolerance, o.out);
  if (!o.out.empty()) std::printf("diff image: %s\n", o.out.c_str());
  if (!ok) std::printf("over tolerance (%s)\n", toleranceText(o.tolerance).c_str());
  return verdict(ok);
}

RunStatus diffFolders(const DiffRequest& o) {
  std::error_code ec;
  const std::vector<std::string> expectedNames = pngNames(o.expected);
  if (expectedNames.empty()) throw InputError(o.expected, "no PNG files in this folder");
  if (!o.out.empty()) makeDiffFolder(o);
  int passed = 0, failed = 0, missing = 0;
  for (const std::string& name : expectedNames) {
    const fs::path actualPath = fs::path(o.actual) / name;
    if (!fs::exists(actualPath, ec)) {
      std::printf("%s: MISSING in %s\n", name.c_str(), o.actual.c_str());
      ++missing;
      continue;
    }
    const std::string diffPath = o.out.empty() ? "" : (fs::path(o.out) / name).string();
    // One unreadable frame fails that frame, not the whole comparison.
    bool ok = false;
    try {
      ok = comparePair(name, fs::path(o.expected) / name, actualPath, o.tolerance, diffPath);
    } catch (const InputError& e) {
      std::printf("%s: FAIL  %s\n", name.c_str(), e.what());
    }
    ++(ok ? passed : failed);
  }
  for (const std::string& name : pngNames(o.actual)) {
    if (!std::binary_search(expectedNames.begin(), expectedNames.end(), name))
      std::printf("%s: only in %s (not compared)\n", name.c_str(), o.actual.c_str());
  }
  const int total = static_cast<int>(expectedNames.size());
  std::printf("%d of %d frames within tolerance", passed, total);
  if (failed > 0) std::printf(", %d over", failed);
  if (missing > 0) std::printf(", %d missing", missing);
  std::printf(" (%s)\n", toleranceText(o.tolerance).c_str());
  if (!o.out.empty()) std::printf("diff images in %s\n", o.out.c_str());
  return verdict(passed == total);
}

}  // namespace

RunStatus runDiff(const DiffRequest& o) {
  std::error_code ec;
  const bool expectedIsFolder = fs::is_directory(o.expected, ec);
  const bool actualIsFolder = fs::is_directory(o.actual, ec);
  for (const std::string& p : {o.expected, o.actual}) {
    if (!fs::exists(p, ec)) throw InputError(p, "no such file or folder");
  }
  if (expectedIsFolder != actualIsFolder) {
    throw InputError(expectedIsFolder ? o.actual : o.expected,
                     "compare two PNG files or two folders, not a file with a folder");
  }
  return expectedIsFolder ? diffFolders(o) : diffFiles(o);
}

}  // namespace vf
