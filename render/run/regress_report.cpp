#include "render/run/regress_report.h"

#include <cstdio>
#include <filesystem>
#include <string>

namespace vf {
namespace {

std::string plural(int n, const char* word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

}  // namespace

std::string checksumLine(const CaseResult& c) {
  const std::string head = "  checksum " + c.checksum + ": ";
  switch (c.checksumStatus) {
    case ChecksumStatus::kOk:
      return head + "ok";
    case ChecksumStatus::kWritten:
      return head + "WRITTEN (was " + c.goldenChecksum + ")";
    case ChecksumStatus::kWrittenNew:
      return head + "WRITTEN (new)";
    case ChecksumStatus::kMissing:
      return head + "MISSING golden " + c.checksumPath + " (run with --update to create it)";
    case ChecksumStatus::kFail:
      break;
  }
  return head + "FAIL, golden " + c.goldenChecksum + ": the physics changed" +
         c.changedRealisations +
         " (the simulated states are not bit-identical; the frames below show whether it is "
         "visible)";
}

namespace {

std::string frameLine(const FrameResult& f, const std::string& reportDir) {
  const std::string head = "  " + f.file + ": ";
  const auto picture = [&](const std::string& file) {
    return " -> " + (std::filesystem::path(reportDir) / file).string();
  };
  switch (f.status) {
    case FrameStatus::kOk:
      return head + "ok    " + f.detail;
    case FrameStatus::kWritten:
      return head + "WRITTEN (was: " + f.detail + ")";
    case FrameStatus::kWrittenNew:
      return head + "WRITTEN (new)";
    case FrameStatus::kFail:
      return head + "FAIL  " + f.detail + picture(f.compareImage);
    case FrameStatus::kUnreadable:
      return head + "FAIL  " + f.detail + picture(f.actualImage);
    case FrameStatus::kMissing:
      break;
  }
  return head + f.detail + picture(f.actualImage);
}

}  // namespace

bool CaseResult::passed() const {
  if (!error.empty() || checksumFailed()) return false;
  for (const FrameResult& f : frames)
    if (f.failed()) return false;
  return true;
}

bool SuiteResult::passed() const {
  for (const CaseResult& c : cases)
    if (!c.passed()) return false;
  return true;
}

std::vector<std::string> caseLines(const CaseResult& c, const std::string& reportDir) {
  if (!c.error.empty()) return {c.name + " (" + c.where + "): ERROR " + c.error};
  std::vector<std::string> lines;
  lines.push_back(c.name + ": " + std::to_string(c.frames.size()) + " frames at " +
                  std::to_string(c.width) + "x" + std::to_string(c.height) + c.what);
  lines.push_back(checksumLine(c));
  for (const FrameResult& f : c.frames) lines.push_back(frameLine(f, reportDir));
  for (const std::string& name : c.stale)
    lines.push_back("  " + name + ": not in suite.toml (an old golden? delete it)");
  return lines;
}

std::string headerLine(const SuiteResult& s) {
  return "voxfall regress " + s.suite + (s.update ? " --update" : "") + " (" + s.backend + ")";
}

std::string closingLine(const SuiteResult& s) {
  int passed = 0, failed = 0, written = 0, checksums = 0, broken = 0;
  for (const CaseResult& c : s.cases) {
    if (!c.error.empty()) ++broken;
    if (c.checksumFailed()) ++checksums;
    if (c.checksumStatus == ChecksumStatus::kWritten ||
        c.checksumStatus == ChecksumStatus::kWrittenNew)
      ++written;
    for (const FrameResult& f : c.frames) {
      if (f.status == FrameStatus::kOk) ++passed;
      if (f.failed()) ++failed;
      if (f.status == FrameStatus::kWritten || f.status == FrameStatus::kWrittenNew) ++written;
    }
  }
  const std::string cases = plural(static_cast<int>(s.cases.size()), "case");
  const std::string notRun = broken ? ", " + plural(broken, "case") + " could not run" : "";
  const bool ok = s.passed();
  if (s.update)
    return std::string(ok ? "UPDATED" : "FAIL") + ": " + cases + ", " + std::to_string(written) +
           " goldens written, " + std::to_string(passed) + " frames kept (within tolerance)" +
           notRun + (written > 0 ? ". Look at the written PNGs before committing them." : "");
  return std::string(ok ? "PASS" : "FAIL") + ": " + cases + ", " + std::to_string(passed) + " of " +
         std::to_string(passed + failed) + " frames passed, " + std::to_string(checksums) +
         " checksums changed or missing" + notRun;
}

std::string xmlEscaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        // XML 1.0 has no other control characters: a stray one would make the file unreadable.
        const bool control = static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t';
        out += control ? ' ' : c;
    }
  }
  return out;
}

std::string timingsText(const SuiteResult& s) {
  std::string out = "case,seconds\n";
  char line[160];
  for (const CaseResult& c : s.cases) {
    std::snprintf(line, sizeof line, "%s,%.3f\n", c.name.c_str(), c.seconds);
    out += line;
  }
  std::snprintf(line, sizeof line, "(all),%.3f\n", s.seconds);
  return out + line;
}

}  // namespace vf
