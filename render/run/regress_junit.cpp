// JUnit XML as CI systems read it (GitLab, Jenkins, GitHub actions that publish test results):
// <testsuites> holding one <testsuite> per case, each with a <testcase> for the trajectory
// checksum and one per checked frame. A failed frame or checksum gets a <failure> whose message
// is the report line's verdict and whose text names the picture; a case that could not run is
// one <testcase name="case"> with an <error>. Frames written by --update pass.
#include <cstdio>
#include <filesystem>
#include <string>

#include "render/run/regress_report.h"

namespace vf {
namespace {

struct Counts {
  int tests = 0, failures = 0, errors = 0;
};

std::string attr(const char* name, const std::string& value) {
  return std::string(" ") + name + "=\"" + xmlEscaped(value) + "\"";
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

std::string testcase(const std::string& suite, const std::string& name, const std::string& failure,
                     const std::string& message, const std::string& text) {
  std::string out = "    <testcase" + attr("classname", suite) + attr("name", name);
  if (failure.empty()) return out + "/>\n";
  return out + ">\n      <" + failure + attr("message", message) + attr("type", name) + ">" +
         xmlEscaped(text) + "</" + failure + ">\n    </testcase>\n";
}

std::string checksumCase(const CaseResult& c, Counts& n) {
  ++n.tests;
  if (!c.checksumFailed()) return testcase(c.name, "checksum", "", "", "");
  ++n.failures;
  const std::string message = c.checksumStatus == ChecksumStatus::kMissing
                                  ? "no golden checksum (run with --update to create it)"
                                  : "the physics changed" + c.changedRealisations;
  return testcase(c.name, "checksum", "failure", message,
                  "checksum " + c.checksum + ", golden " + c.goldenChecksum);
}

std::string frameCase(const CaseResult& c, const FrameResult& f, const std::string& reportDir,
                      Counts& n) {
  ++n.tests;
  if (!f.failed()) return testcase(c.name, f.file, "", "", "");
  ++n.failures;
  const std::string picture = f.compareImage.empty() ? f.actualImage : f.compareImage;
  return testcase(c.name, f.file, "failure", f.detail,
                  f.detail + "\npicture: " + (std::filesystem::path(reportDir) / picture).string());
}

std::string suiteOf(const CaseResult& c, const std::string& reportDir, Counts& total) {
  Counts n;
  std::string body;
  if (!c.error.empty()) {
    n.tests = n.errors = 1;
    body = testcase(c.name, "case", "error", c.error, c.where + ": " + c.error);
  } else {
    body = checksumCase(c, n);
    for (const FrameResult& f : c.frames) body += frameCase(c, f, reportDir, n);
  }
  total.tests += n.tests, total.failures += n.failures, total.errors += n.errors;
  return "  <testsuite" + attr("name", c.name) + attr("tests", std::to_string(n.tests)) +
         attr("failures", std::to_string(n.failures)) + attr("errors", std::to_string(n.errors)) +
         attr("skipped", "0") + attr("time", seconds(c.seconds)) + ">\n" + body +
         "  </testsuite>\n";
}

}  // namespace

std::string junitXml(const SuiteResult& s, const std::string& reportDir) {
  Counts total;
  std::string suites;
  for (const CaseResult& c : s.cases) suites += suiteOf(c, reportDir, total);
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites" +
         attr("name", "voxfall regress " + s.suite) + attr("tests", std::to_string(total.tests)) +
         attr("failures", std::to_string(total.failures)) +
         attr("errors", std::to_string(total.errors)) + attr("time", seconds(s.seconds)) + ">\n" +
         suites + "</testsuites>\n";
}

}  // namespace vf
