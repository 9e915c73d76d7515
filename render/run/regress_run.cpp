#include "render/run/regress_run.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "render/gl/gl_context.h"
#include "render/gl/shader_program.h"
#include "render/output/output_file.h"
#include "render/regress_suite.h"
#include "render/run/regress_case.h"
#include "sim/core/error.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// --- a case's result between processes (a worker's file, read back by the parent) ----------
// Doubles go through the JSON library's shortest round-trip form, so they come back bit-exact.

// JSON has no infinity: the PSNR of identical frames travels as the string "inf".
json psnrJson(double psnr) { return std::isinf(psnr) ? json("inf") : json(psnr); }

json toJson(const FrameResult& f) {
  const DiffMetrics& m = f.metrics;
  json j = {{"frame", f.frame},
            {"file", f.file},
            {"status", static_cast<int>(f.status)},
            {"compared", f.compared},
            {"detail", f.detail},
            {"expected", f.expectedImage},
            {"actual", f.actualImage},
            {"diff", f.diffImage},
            {"compare", f.compareImage},
            {"m",
             {m.width, m.height, m.sameSize, m.maxChannelDiff, m.differingPixels, m.pixels,
              m.maskedPixels, m.differingFraction, psnrJson(m.psnr), m.threshold, m.ssim}}};
  if (f.crop) j["crop"] = {f.crop->x, f.crop->y, f.crop->width, f.crop->height};
  return j;
}

FrameResult frameFromJson(const json& j) {
  FrameResult f;
  f.frame = j["frame"], f.file = j["file"], f.status = static_cast<FrameStatus>(j["status"]);
  f.compared = j["compared"], f.detail = j["detail"];
  f.expectedImage = j["expected"], f.actualImage = j["actual"];
  f.diffImage = j["diff"], f.compareImage = j["compare"];
  const json& m = j["m"];
  const double psnr =
      m[8].is_string() ? std::numeric_limits<double>::infinity() : m[8].get<double>();
  f.metrics = {m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], psnr, m[9], m[10]};
  if (j.contains("crop"))
    f.crop = PixelRect{j["crop"][0], j["crop"][1], j["crop"][2], j["crop"][3]};
  return f;
}

json toJson(const CaseResult& c) {
  json frames = json::array();
  for (const FrameResult& f : c.frames) frames.push_back(toJson(f));
  return {{"name", c.name},
          {"where", c.where},
          {"error", c.error},
          {"width", c.width},
          {"height", c.height},
          {"what", c.what},
          {"seconds", c.seconds},
          {"sum_status", static_cast<int>(c.checksumStatus)},
          {"sum", c.checksum},
          {"golden", c.goldenChecksum},
          {"sum_path", c.checksumPath},
          {"changed", c.changedRealisations},
          {"frames", frames},
          {"stale", c.stale}};
}

CaseResult caseFromJson(const json& j) {
  CaseResult c;
  c.name = j["name"], c.where = j["where"], c.error = j["error"];
  c.width = j["width"], c.height = j["height"], c.what = j["what"], c.seconds = j["seconds"];
  c.checksumStatus = static_cast<ChecksumStatus>(j["sum_status"]);
  c.checksum = j["sum"], c.goldenChecksum = j["golden"], c.checksumPath = j["sum_path"];
  c.changedRealisations = j["changed"];
  for (const json& f : j["frames"]) c.frames.push_back(frameFromJson(f));
  c.stale = j["stale"].get<std::vector<std::string>>();
  return c;
}

// --- running cases ---------------------------------------------------------------------------

std::vector<SuiteCase> selectedCases(const Suite& suite, const RegressRequest& r) {
  for (const std::string& name : r.cases)
    if (std::none_of(suite.cases.begin(), suite.cases.end(),
                     [&](const SuiteCase& c) { return c.name == name; }))
      throw InputError(r.suite, "--case " + name + ": no case of that name in suite.toml");
  std::vector<SuiteCase> out;
  for (const SuiteCase& c : suite.cases)
    if (r.cases.empty() || std::find(r.cases.begin(), r.cases.end(), c.name) != r.cases.end())
      out.push_back(c);
  return out;
}

// A case that cannot run fails alone; the others still run.
CaseResult runOrReport(const SuiteCase& c, const Suite& suite, const fs::path& reportDir,
                       bool update, gl::Context& context, const std::string& shaderDir) {
  try {
    return runRegressionCase(c, suite.dir, reportDir, update, context, shaderDir);
  } catch (const std::exception& e) {
    CaseResult r;
    r.name = c.name;
    r.where = c.where;
    r.error = e.what();
    return r;
  }
}

struct Worker {
  pid_t pid = -1;
  // One JSON result per line, in the order of its cases: a temporary file, never committed, so
  // it goes when read, or with the run when a signal ends it.
  std::unique_ptr<OutputFile> results;
};

// A worker process: its own GL context, cases k, k + jobs, ...; never returns.
[[noreturn]] void workerMain(int k, const std::vector<SuiteCase>& cases, const Suite& suite,
                             const RegressRequest& r, const fs::path& reportDir,
                             const fs::path& results) {
  int status = 0;
  try {
    auto context = gl::createContext(gl::parseBackend(r.gl));
    const std::string shaderDir = gl::findShaderDir(r.shaders);
    std::ofstream out(results);
    out << json(context->description()).dump() << "\n";  // the report's header names it
    for (std::size_t i = static_cast<std::size_t>(k); i < cases.size();
         i += static_cast<std::size_t>(r.jobs))
      out << toJson(runOrReport(cases[i], suite, reportDir, r.update, *context, shaderDir)).dump()
          << "\n"
          << std::flush;
    if (!out) status = 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "voxfall: error: regress worker %d: %s\n", k, e.what());
    status = 2;
  }
  std::fflush(nullptr);
  _exit(status);  // no exit handlers or destructors of the parent's objects in the child
}

// A case whose worker died before reporting it.
CaseResult lostCase(const SuiteCase& c, const std::string& why) {
  CaseResult r;
  r.name = c.name;
  r.where = c.where;
  r.error = "the worker process that ran this case " + why;
  return r;
}

std::string exitWords(int status) {
  if (WIFSIGNALED(status)) return "was killed by signal " + std::to_string(WTERMSIG(status));
  return "ended with exit code " + std::to_string(WEXITSTATUS(status));
}

// The cases' results in case order, and the GL description of the first worker.
std::vector<CaseResult> runInWorkers(const std::vector<SuiteCase>& cases, const Suite& suite,
                                     const RegressRequest& r, const fs::path& reportDir,
                                     std::string& backend) {
  const int jobs = std::min<int>(r.jobs, static_cast<int>(cases.size()));
  std::vector<Worker> workers(static_cast<std::size_t>(jobs));
  std::fflush(nullptr);  // nothing buffered may be written twice
  for (int k = 0; k < jobs; ++k) {
    Worker& w = workers[static_cast<std::size_t>(k)];
    w.results = std::make_unique<OutputFile>(
        (reportDir / ("regress-worker-" + std::to_string(k) + ".jsonl")).string(),
        replaceOutputs());
    w.results->closeStream();  // the worker writes it by name
    w.pid = forkWorker();
    if (w.pid < 0) throw InputError(reportDir.string(), "cannot start a worker process");
    if (w.pid == 0) workerMain(k, cases, suite, r, reportDir, w.results->tempPath());
  }
  std::vector<CaseResult> results(cases.size());
  for (int k = 0; k < jobs; ++k) {
    Worker& w = workers[static_cast<std::size_t>(k)];
    int status = 0;
    ::waitpid(w.pid, &status, 0);
    workerEnded(w.pid);
    std::ifstream in(w.results->tempPath());
    std::string line;
    if (std::getline(in, line) && backend.empty()) backend = json::parse(line).get<std::string>();
    for (std::size_t i = static_cast<std::size_t>(k); i < cases.size();
         i += static_cast<std::size_t>(jobs))
      results[i] = std::getline(in, line) ? caseFromJson(json::parse(line))
                                          : lostCase(cases[i], exitWords(status));
  }
  return results;
}

void writeText(const fs::path& path, const std::string& text) {
  OutputFile file(path.string(), replaceOutputs());
  std::fputs(text.c_str(), file.stream());
  file.commit();
}

void writeReports(const SuiteResult& s, const RegressRequest& r, const fs::path& reportDir) {
  std::string report = headerLine(s) + "\n";
  for (const CaseResult& c : s.cases)
    for (const std::string& line : caseLines(c, reportDir.string())) report += line + "\n";
  report += closingLine(s) + "\n";
  writeText(reportDir / "report.txt", report);
  writeText(reportDir / "index.html", htmlReport(s));
  writeText(reportDir / "timings.txt", timingsText(s));
  if (!r.junitFile.empty()) writeText(r.junitFile, junitXml(s, reportDir.string()));
}

}  // namespace

std::string reportFolder(const RegressRequest& request) {
  return request.reportDir.empty() ? "out/regress" : request.reportDir;
}

SuiteResult runRegression(const RegressRequest& r, const RegressProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  std::error_code ec;
  if (!fs::is_directory(r.suite, ec))
    throw InputError(r.suite, "not a folder (a suite is a folder holding suite.toml)");
  const Suite suite = readSuite((fs::path(r.suite) / "suite.toml").string());
  const std::vector<SuiteCase> cases = selectedCases(suite, r);
  const fs::path reportDir = reportFolder(r);
  fs::create_directories(reportDir, ec);
  if (ec) throw InputError(reportDir.string(), "cannot create the report folder: " + ec.message());

  SuiteResult s;
  s.suite = fs::path(r.suite).string();
  s.update = r.update;
  if (r.jobs > 1 && cases.size() > 1) {
    s.cases = runInWorkers(cases, suite, r, reportDir, s.backend);
    if (progress.onStart) progress.onStart(s);
    if (progress.onCase)
      for (const CaseResult& c : s.cases) progress.onCase(c);
  } else {
    // GL and shaders once for the whole suite: a missing library fails here, in seconds.
    auto context = gl::createContext(gl::parseBackend(r.gl));
    const std::string shaderDir = gl::findShaderDir(r.shaders);
    s.backend = context->description();
    if (progress.onStart) progress.onStart(s);
    for (const SuiteCase& c : cases) {
      s.cases.push_back(runOrReport(c, suite, reportDir, r.update, *context, shaderDir));
      if (progress.onCase) progress.onCase(s.cases.back());
    }
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeReports(s, r, reportDir);
  return s;
}

}  // namespace vf
