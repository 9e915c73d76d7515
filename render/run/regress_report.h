// What a regression run found, case by case and frame by frame, and the three reports made from
// it: the text report (stdout and report.txt), the HTML page a reviewer opens (index.html) and
// JUnit XML for CI systems. The results hold no pixels: the pictures of a failing frame are
// files in the report folder, named here. Timings are kept in one place, CaseResult::seconds:
// report.txt and index.html leave them out, so a run gives the same report bytes however it
// was split over processes; timings.txt and the JUnit file carry them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "render/output/image_diff.h"
#include "render/output/pixel_mask.h"

namespace vf {

enum class FrameStatus { kOk, kFail, kMissing, kUnreadable, kWritten, kWrittenNew };
enum class ChecksumStatus { kOk, kFail, kMissing, kWritten, kWrittenNew };

struct FrameResult {
  int frame = 0;
  std::string file;  // frame_NNNN.png
  FrameStatus status = FrameStatus::kOk;
  bool compared = false;  // metrics hold a comparison with the golden
  DiffMetrics metrics;
  std::string detail;             // describe() of the metrics, or why the golden could not be read
  std::optional<PixelRect> crop;  // around the change (compare_image.h), for failing frames
  // Report files, relative to the report folder; "" where none was written.
  std::string expectedImage, actualImage, diffImage, compareImage;
  // Over tolerance, or without a golden to compare with (missing or unreadable).
  bool failed() const {
    return status == FrameStatus::kFail || status == FrameStatus::kMissing ||
           status == FrameStatus::kUnreadable;
  }
};

struct CaseResult {
  std::string name;
  std::string where;  // suite.toml:LINE of its [[case]]
  std::string error;  // non-empty: the case could not run (and nothing below is set)
  int width = 0, height = 0;
  std::string what;  // "" or ", 3 ensemble realisations"
  double seconds = 0;
  ChecksumStatus checksumStatus = ChecksumStatus::kOk;
  std::string checksum, goldenChecksum;  // words joined by spaces (one per realisation)
  std::string checksumPath;              // the golden checksum.txt
  std::string changedRealisations;       // " (realisations 1, 2)" or ""
  std::vector<FrameResult> frames;
  std::vector<std::string> stale;  // goldens in the folder that no frame lists
  bool checksumFailed() const {
    return checksumStatus == ChecksumStatus::kFail || checksumStatus == ChecksumStatus::kMissing;
  }
  bool passed() const;
};

struct SuiteResult {
  std::string suite;    // the suite folder as given
  std::string backend;  // the GL context's description
  bool update = false;
  std::vector<CaseResult> cases;
  double seconds = 0;
  bool passed() const;
};

// The text report: every line of one case (pictures named under `reportDir`), then the closing
// line of the whole run.
std::vector<std::string> caseLines(const CaseResult& c, const std::string& reportDir);
std::string headerLine(const SuiteResult& s);
std::string checksumLine(const CaseResult& c);
std::string closingLine(const SuiteResult& s);

// One self-contained HTML page (styles and script inline, images by paths relative to the
// report folder), for a browser from file:// (regress_html.cpp).
std::string htmlReport(const SuiteResult& s);

// JUnit XML: one <testsuite> per case, one <testcase> per checked frame and per checksum, a
// <failure> with the metrics for each that failed, an <error> for a case that could not run
// (regress_junit.cpp). `reportDir` is named in the failures, where the pictures are.
std::string junitXml(const SuiteResult& s, const std::string& reportDir);

// Text with &, <, >, " and ' escaped for HTML and XML.
std::string xmlEscaped(const std::string& text);

// "case,seconds" per case and the total: the run's timings.
std::string timingsText(const SuiteResult& s);

}  // namespace vf
