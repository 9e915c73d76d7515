// index.html of a regression report: one page that needs nothing but the files beside it (no
// network, styles and script inline), listing every case with its checksum verdict and every
// frame with its status and metrics. A failing frame shows expected, actual and diff under
// labels; a slider that uncovers the actual frame over the expected one, and a button that
// blinks between them; and the three cropped around the change at 4x (the crop found from the
// diff, compare_image.h, drawn by CSS from the full pictures). Passing frames are collapsed.
// The page's script marks <body> with how many images loaded (data-images-loaded,
// data-images-broken), which a test reads in a headless browser.
#include <string>

#include "render/output/compare_image.h"
#include "render/run/regress_report.h"

namespace vf {
namespace {

constexpr const char* kStyle = R"(
body { font: 14px/1.4 system-ui, sans-serif; margin: 1.5em; color: #222; background: #fafafa; }
h1 .pass, h2 .pass, .ok { color: #1a7f37; } h1 .fail, h2 .fail, .bad { color: #c62828; }
section.case { border: 1px solid #ddd; border-radius: 6px; padding: 0.5em 1em; margin: 1em 0;
  background: #fff; }
.metrics { font-family: ui-monospace, monospace; font-size: 12px; }
.views { display: flex; gap: 8px; flex-wrap: wrap; }
figure { margin: 0; } figcaption { font-weight: 600; font-size: 12px; text-transform: uppercase; }
img.frame { display: block; border: 1px solid #ccc; }
.stack { position: relative; display: inline-block; }
.stack img.over { position: absolute; left: 0; top: 0; }
.crop { position: relative; overflow: hidden; border: 1px solid #ccc; }
.crop img { position: absolute; image-rendering: pixelated; max-width: none; }
)";

constexpr const char* kScript = R"(
for (const box of document.querySelectorAll('.compare')) {
  const over = box.querySelector('img.over');
  const slider = box.querySelector('input.slider');
  const show = () => { over.style.clipPath = 'inset(0 ' + (100 - slider.value) + '% 0 0)'; };
  slider.addEventListener('input', show);
  show();
  let timer = null;
  box.querySelector('button.blink').addEventListener('click', (e) => {
    if (timer) { clearInterval(timer); timer = null; over.style.visibility = 'visible';
      e.target.textContent = 'blink'; return; }
    slider.value = 100; show();
    timer = setInterval(() => { over.style.visibility =
      over.style.visibility === 'hidden' ? 'visible' : 'hidden'; }, 500);
    e.target.textContent = 'stop';
  });
}
window.addEventListener('load', () => {
  const images = [...document.images];
  const loaded = images.filter((i) => i.complete && i.naturalWidth > 0).length;
  document.body.dataset.imagesLoaded = loaded;
  document.body.dataset.imagesBroken = images.length - loaded;
});
)";

constexpr const char* kLegend =
    "<p>For a failing frame: the expected (golden) and actual frames, and the diff: red where a "
    "pixel differs by more than the case's threshold, blue where it differs by less, dim grey "
    "where equal. The slider uncovers the actual frame over the expected one from the left; "
    "blink alternates them. The enlarged crops (outlined in the compare picture beside the "
    "report) show the part of the frame with the most differing pixels.</p>\n";

std::string e(const std::string& text) { return xmlEscaped(text); }

std::string verdict(bool passed) {
  return passed ? "<span class=\"pass\">PASS</span>" : "<span class=\"fail\">FAIL</span>";
}

std::string figure(const std::string& caption, const std::string& src) {
  return "<figure><figcaption>" + caption + "</figcaption><img class=\"frame\" src=\"" + e(src) +
         "\" alt=\"" + caption + "\"></figure>";
}

std::string px(int v) { return std::to_string(v) + "px"; }

// The crop of one picture at kCompareZoom: the whole picture enlarged, shifted, clipped.
std::string cropView(const std::string& caption, const std::string& src, const PixelRect& r,
                     int width, int height) {
  const int z = kCompareZoom;
  return "<figure><figcaption>" + caption + " " + std::to_string(z) +
         "x</figcaption><div class=\"crop\" style=\"width:" + px(r.width * z) +
         ";height:" + px(r.height * z) + "\"><img src=\"" + e(src) + "\" alt=\"" + caption +
         " crop\" style=\"width:" + px(width * z) + ";height:" + px(height * z) +
         ";left:" + px(-r.x * z) + ";top:" + px(-r.y * z) + "\"></div></figure>";
}

std::string comparison(const FrameResult& f) {
  return "<div class=\"compare\"><div class=\"stack\"><img class=\"frame under\" src=\"" +
         e(f.expectedImage) + "\" alt=\"expected\"><img class=\"frame over\" src=\"" +
         e(f.actualImage) +
         "\" alt=\"actual\"></div><div><label>expected &#8596; actual <input class=\"slider\" "
         "type=\"range\" min=\"0\" max=\"100\" value=\"50\"></label> <button class=\"blink\" "
         "type=\"button\">blink</button></div></div>";
}

std::string failingFrame(const CaseResult& c, const FrameResult& f) {
  std::string out = "<div class=\"frame failing\" data-frame=\"" + std::to_string(f.frame) +
                    "\"><h3>" + e(f.file) + ": <span class=\"fail\">FAIL</span></h3><p " +
                    "class=\"metrics\">" + e(f.detail) + "</p>";
  if (f.expectedImage.empty())  // no golden to compare with
    return out + "<div class=\"views\">" + figure("actual", f.actualImage) + "</div></div>";
  out += "<div class=\"views\">" + figure("expected", f.expectedImage) +
         figure("actual", f.actualImage) + figure("diff", f.diffImage) + "</div>" + comparison(f);
  if (f.crop)
    out += "<div class=\"views\">" +
           cropView("expected", f.expectedImage, *f.crop, c.width, c.height) +
           cropView("actual", f.actualImage, *f.crop, c.width, c.height) +
           cropView("diff", f.diffImage, *f.crop, c.width, c.height) + "</div>";
  return out + "</div>";
}

std::string passingFrames(const CaseResult& c) {
  std::string items;
  int n = 0;
  for (const FrameResult& f : c.frames) {
    if (f.failed()) continue;
    ++n;
    items += "<li><span class=\"ok\">" + e(f.file) + "</span> <span class=\"metrics\">" +
             e(f.detail) + "</span></li>";
  }
  if (n == 0) return "";
  return "<details><summary>" + std::to_string(n) + " frame" + (n == 1 ? "" : "s") +
         " passed</summary><ul>" + items + "</ul></details>";
}

std::string caseSection(const CaseResult& c) {
  std::string out = "<section class=\"case\" id=\"case-" + e(c.name) + "\" data-case=\"" +
                    e(c.name) + "\" data-passed=\"" + (c.passed() ? "1" : "0") + "\"><h2>" +
                    e(c.name) + " " + verdict(c.passed()) + "</h2>";
  if (!c.error.empty())
    return out + "<p class=\"bad\">" + e(c.where) + ": " + e(c.error) + "</p></section>";
  out += "<p>" + std::to_string(c.frames.size()) + " frames at " + std::to_string(c.width) + "x" +
         std::to_string(c.height) + e(c.what) + "</p>";
  out += "<p class=\"metrics " + std::string(c.checksumFailed() ? "bad" : "ok") + "\">" +
         e(checksumLine(c)) + "</p>";
  for (const FrameResult& f : c.frames)
    if (f.failed()) out += failingFrame(c, f);
  return out + passingFrames(c) + "</section>";
}

}  // namespace

std::string htmlReport(const SuiteResult& s) {
  std::string body;
  int failed = 0;
  for (const CaseResult& c : s.cases) {
    body += caseSection(c) + "\n";
    if (!c.passed()) ++failed;
  }
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>voxfall "
         "regress " +
         e(s.suite) + "</title><style>" + kStyle + "</style></head>\n<body data-cases=\"" +
         std::to_string(s.cases.size()) + "\" data-failed=\"" + std::to_string(failed) +
         "\"><h1>voxfall regress " + verdict(s.passed()) + "</h1><p class=\"metrics\">" +
         e(headerLine(s)) + "<br>" + e(closingLine(s)) + "</p>\n" + kLegend + body + "<script>" +
         kScript + "</script></body></html>\n";
}

}  // namespace vf
