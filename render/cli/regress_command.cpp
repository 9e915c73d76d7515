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
// --update writes the goldens that are missing or fail (each through a temporary file and a
// rename) and keeps the ones within tolerance, so that a review of the change (`git diff`,
// looking at the PNGs) shows only what really changed. To regenerate a case from scratch,
// delete its folder and run --update.
//
// suite.toml is read by a small reader of a TOML subset (below) rather than toml++: the style
// guide keeps toml++ in the scene loader alone, and a suite needs only `[[case]]` tables of
// `key = value` lines with strings, numbers and one-line number arrays. Anything else is an
// error naming file:line:column, as scene errors do, so the file stays valid TOML.
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
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "render/cli/commands.h"
#include "render/cli/scene_playback.h"
#include "render/cli/run_output.h"
#include "render/gl/gl_context.h"
#include "render/gl/shader_program.h"
#include "render/output/image_diff.h"
#include "render/output/png_writer.h"
#include "sim/core/error.h"
#include "sim/scene/scene.h"

namespace vf::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSuiteFile = "suite.toml";
constexpr const char* kGoldenPattern = "frame_####.png";
constexpr const char* kChecksumFile = "checksum.txt";

// --- suite.toml -----------------------------------------------------------------------------

struct SuiteCase {
  std::string name;          // folder of its goldens; default: the scene file's stem
  std::string scene;         // resolved against the suite folder
  std::vector<int> frames;   // frame numbers k (t = k / fps), in the order given
  std::optional<int> width;  // default: the scene's [output] size
  std::optional<int> height;
  DiffTolerance tolerance;
  std::string where;  // "suite.toml:LINE" of its [[case]] header
};

struct Suite {
  fs::path dir;
  std::vector<SuiteCase> cases;
};

// A parsed right-hand side: a string, a number, or a one-line array of numbers.
struct Value {
  enum class Kind { string, number, array } kind = Kind::number;
  std::string text;
  double number = 0;
  std::vector<double> numbers;
  bool integral = false;  // number (or every array element) written as an integer
};

class SuiteReader {
 public:
  explicit SuiteReader(fs::path file) : file_(std::move(file)) {}

  Suite read() {
    std::ifstream in(file_);
    if (!in) {
      throw InputError(file_.string(),
                       "cannot read the suite file (a suite folder holds suite.toml)");
    }
    Suite suite;
    suite.dir = file_.parent_path();
    DiffTolerance defaults;  // top-level threshold / max_fraction apply to later cases
    std::string raw;
    std::set<std::string> keysSeen;  // in the current table
    while (std::getline(in, raw)) {
      ++line_;
      const std::string text = stripComment(raw);
      const std::size_t start = text.find_first_not_of(" \t\r");
      if (start == std::string::npos) continue;
      const std::string body = trim(text);
      if (body[0] == '[') {
        if (body != "[[case]]") {
          fail(start, "only [[case]] tables may appear in a suite file, not '" + body + "'");
        }
        finishCase(suite);
        current_ = SuiteCase{};
        current_->tolerance = defaults;
        current_->where = sourceLocation(file_.string(), line_);
        keysSeen.clear();
        continue;
      }
      const std::size_t eq = text.find('=');
      if (eq == std::string::npos) fail(start, "expected 'key = value' or [[case]]");
      const std::string key = trim(text.substr(0, eq));
      if (key.empty() || !std::all_of(key.begin(), key.end(), [](unsigned char c) {
            return std::isalnum(c) || c == '_' || c == '-';
          })) {
        fail(start, "'" + key + "' is not a key");
      }
      if (!keysSeen.insert(key).second) fail(start, "'" + key + "' is given twice");
      const std::size_t valueStart = text.find_first_not_of(" \t", eq + 1);
      if (valueStart == std::string::npos) fail(eq, "'" + key + "' has no value");
      const Value value = parseValue(text, valueStart);
      if (current_) {
        readCaseKey(*current_, key, value, start, valueStart);
      } else {
        readTopKey(defaults, key, value, start, valueStart);
      }
    }
    finishCase(suite);
    if (suite.cases.empty()) {
      throw InputError(file_.string(),
                       "no [[case]] in the suite file (see tests/golden/README.md)");
    }
    return suite;
  }

 private:
  [[noreturn]] void fail(std::size_t column, const std::string& message) const {
    throw InputError(sourceLocation(file_.string(), line_, static_cast<int>(column) + 1), message);
  }

  static std::string trim(const std::string& s) {
    const std::size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    const std::size_t b = s.find_last_not_of(" \t\r");
    return s.substr(a, b - a + 1);
  }

  // The line up to a '#' that is not inside a string.
  static std::string stripComment(const std::string& s) {
    bool inString = false;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (inString && s[i] == '\\') {
        ++i;
      } else if (s[i] == '"') {
        inString = !inString;
      } else if (s[i] == '#' && !inString) {
        return s.substr(0, i);
      }
    }
    return s;
  }

  // A number starting at `pos`; advances `pos` past it.
  double parseNumber(const std::string& s, std::size_t& pos, bool& integral) const {
    const char* begin = s.c_str() + pos;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(v)) fail(pos, "expected a number");
    const std::string written(begin, static_cast<std::size_t>(end - begin));
    integral = written.find_first_of(".eEnNiI") == std::string::npos;
    pos += static_cast<std::size_t>(end - begin);
    return v;
  }

  Value parseValue(const std::string& s, std::size_t pos) const {
    Value v;
    if (s[pos] == '"') {
      v.kind = Value::Kind::string;
      std::size_t i = pos + 1;
      for (; i < s.size() && s[i] != '"'; ++i) {
        if (s[i] == '\\') {
          if (i + 1 >= s.size() || (s[i + 1] != '"' && s[i + 1] != '\\'))
            fail(i, "only \\\" and \\\\ escapes are supported in suite strings");
          ++i;
        }
        v.text += s[i];
      }
      if (i >= s.size()) fail(pos, "unterminated string");
      pos = i + 1;
    } else if (s[pos] == '[') {
      v.kind = Value::Kind::array;
      v.integral = true;
      ++pos;
      while (true) {
        pos = s.find_first_not_of(" \t", pos);
        if (pos == std::string::npos)
          fail(s.size(), "unterminated array (arrays must fit on one line)");
        if (s[pos] == ']') break;
        bool integral = false;
        v.numbers.push_back(parseNumber(s, pos, integral));
        v.integral = v.integral && integral;
        pos = s.find_first_not_of(" \t", pos);
        if (pos != std::string::npos && s[pos] == ',') {
          ++pos;
        } else if (pos == std::string::npos || s[pos] != ']') {
          fail(pos == std::string::npos ? s.size() : pos, "expected ',' or ']' in the array");
        }
      }
      ++pos;
    } else {
      v.kind = Value::Kind::number;
      v.number = parseNumber(s, pos, v.integral);
    }
    const std::size_t rest = s.find_first_not_of(" \t\r", pos);
    if (rest != std::string::npos) fail(rest, "unexpected text after the value");
    return v;
  }

  int readInt(const Value& v, std::size_t column, const std::string& key, int lo, int hi) const {
    if (v.kind != Value::Kind::number || !v.integral || v.number < lo || v.number > hi) {
      fail(column,
           "'" + key + "' must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    }
    return static_cast<int>(v.number);
  }

  double readFraction(const Value& v, std::size_t column, const std::string& key) const {
    if (v.kind != Value::Kind::number || v.number < 0 || v.number > 1)
      fail(column, "'" + key + "' must be a number in 0..1 (a share of the pixels)");
    return v.number;
  }

  void readTopKey(DiffTolerance& t, const std::string& key, const Value& v, std::size_t keyCol,
                  std::size_t valueCol) const {
    if (key == "threshold") {
      t.threshold = readInt(v, valueCol, key, 0, 255);
    } else if (key == "max_fraction") {
      t.maxFraction = readFraction(v, valueCol, key);
    } else {
      fail(keyCol, "unknown key '" + key +
                       "' before the first [[case]] (valid there: "
                       "threshold, max_fraction)");
    }
  }

  void readCaseKey(SuiteCase& c, const std::string& key, const Value& v, std::size_t keyCol,
                   std::size_t valueCol) const {
    if (key == "name") {
      const bool valid = v.kind == Value::Kind::string && !v.text.empty() && v.text != "." &&
                         v.text != ".." &&
                         std::all_of(v.text.begin(), v.text.end(), [](unsigned char ch) {
                           return std::isalnum(ch) || ch == '_' || ch == '-' || ch == '.';
                         });
      if (!valid) fail(valueCol, "'name' must be a folder name (letters, digits, _ - .)");
      c.name = v.text;
    } else if (key == "scene") {
      if (v.kind != Value::Kind::string || v.text.empty())
        fail(valueCol, "'scene' must be the path of a scene file, relative to the suite folder");
      const fs::path scene =
          fs::path(v.text).is_absolute() ? fs::path(v.text) : file_.parent_path() / v.text;
      std::error_code ec;
      if (!fs::is_regular_file(scene, ec))
        fail(valueCol, "scene file '" + scene.string() + "' not found");
      c.scene = scene.lexically_normal().string();
    } else if (key == "frames") {
      if (v.kind != Value::Kind::array || v.numbers.empty() || !v.integral)
        fail(valueCol, "'frames' must be a list of frame numbers, e.g. [0, 30, 60]");
      std::set<int> seen;
      for (const double k : v.numbers) {
        if (k < 0 || k > 1e7) fail(valueCol, "frame numbers must be >= 0");
        if (!seen.insert(static_cast<int>(k)).second)
          fail(valueCol, "frame " + std::to_string(static_cast<int>(k)) + " is listed twice");
        c.frames.push_back(static_cast<int>(k));
      }
    } else if (key == "size") {
      if (v.kind != Value::Kind::array || v.numbers.size() != 2 || !v.integral ||
          v.numbers[0] < 16 || v.numbers[1] < 16 || v.numbers[0] > 8192 || v.numbers[1] > 8192)
        fail(valueCol, "'size' must be [width, height] in pixels, each 16..8192");
      c.width = static_cast<int>(v.numbers[0]);
      c.height = static_cast<int>(v.numbers[1]);
    } else if (key == "threshold") {
      c.tolerance.threshold = readInt(v, valueCol, key, 0, 255);
    } else if (key == "max_fraction") {
      c.tolerance.maxFraction = readFraction(v, valueCol, key);
    } else {
      fail(keyCol, "unknown key '" + key +
                       "' in [[case]] (valid: name, scene, frames, size, "
                       "threshold, max_fraction)");
    }
  }

  void finishCase(Suite& suite) {
    if (!current_) return;
    SuiteCase& c = *current_;
    if (c.scene.empty()) throw InputError(c.where, "[[case]] needs 'scene = \"path.toml\"'");
    if (c.frames.empty()) throw InputError(c.where, "[[case]] needs 'frames = [k, ...]'");
    if (c.name.empty()) c.name = fs::path(c.scene).stem().string();
    for (const SuiteCase& other : suite.cases) {
      if (other.name == c.name) {
        throw InputError(c.where, "a second case named '" + c.name + "' (the first is at " +
                                      other.where + "); give one a different 'name'");
      }
    }
    suite.cases.push_back(std::move(c));
    current_.reset();
  }

  fs::path file_;
  int line_ = 0;
  std::optional<SuiteCase> current_;
};

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

std::string readChecksum(const fs::path& path) {
  std::ifstream in(path);
  std::string word;
  in >> word;
  return word;
}

// checksum.txt through a temporary file and a rename (OutputFile), like every other output.
void writeChecksum(const fs::path& path, const std::string& checksum) {
  OutputFile file(path.string());
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

void runCase(const SuiteCase& c, const fs::path& suiteDir, const fs::path& reportDir, bool update,
             gl::Context& context, const std::string& shaderDir, ReportLog& log, Counts& counts) {
  const auto start = std::chrono::steady_clock::now();
  SceneSpec spec = loadScene(c.scene);
  if (c.width) spec.output.width = *c.width;
  if (c.height) spec.output.height = *c.height;
  const RenderedFrames rendered = renderSceneFrames(spec, c.frames, context, shaderDir);
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
  char head[160];
  std::snprintf(head, sizeof head, "%s: %zu frames at %dx%d in %.1f s", c.name.c_str(),
                c.frames.size(), spec.output.width, spec.output.height, seconds);
  log.line(head);

  // The trajectory checksum.
  const std::string checksum = rendered.summary.checksumHex();
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
    log.line("  checksum " + checksum + ": FAIL, golden " + golden +
             ": the physics changed (the simulated states are not bit-identical; the frames "
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
  Suite suite = SuiteReader(suiteDir / kSuiteFile).read();
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
    OutputFile report(reportFile.string());
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
