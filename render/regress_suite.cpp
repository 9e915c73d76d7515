// suite.toml through toml++ (its source regions give each error its line and column).
#include "render/regress_suite.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include "sim/core/error.h"
#include "sim/scene/scene.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// Realisations of one ensemble case: each is stepped to its end and drawn with the others, so a
// suite case of more than a few hundred is a mistake, not a test.
constexpr int kMaxRuns = 1000;

class SuiteReader {
 public:
  explicit SuiteReader(std::string file) : file_(std::move(file)) {}

  Suite read() {
    toml::table root;
    try {
      root = toml::parse_file(file_);
    } catch (const toml::parse_error& e) {
      const auto& b = e.source().begin;
      std::error_code ec;
      if (!fs::is_regular_file(file_, ec))
        throw InputError(file_, "cannot read the suite file (a suite folder holds suite.toml)");
      throw InputError(sourceLocation(file_, static_cast<int>(b.line), static_cast<int>(b.column)),
                       std::string(e.description()));
    }
    Suite suite;
    suite.dir = fs::path(file_).parent_path().string();
    DiffTolerance defaults;
    for (auto&& [key, value] : root) {
      if (key.str() == "case") continue;
      if (key.str() == "threshold") {
        defaults.threshold = integer(value, "threshold", 0, 255);
      } else if (key.str() == "max_fraction") {
        defaults.maxFraction = fraction(value, "max_fraction");
      } else if (key.str() == "min_ssim") {
        defaults.minSsim = fraction(value, "min_ssim");
      } else {
        fail(key.source(), "unknown key '" + std::string(key.str()) +
                               "' outside [[case]] (valid there: threshold, max_fraction, "
                               "min_ssim)");
      }
    }
    if (const toml::node* cases = root.get("case")) {
      const toml::array* list = cases->as_array();
      if (list == nullptr || !list->is_array_of_tables())
        fail(cases->source(), "only [[case]] tables may appear in a suite file");
      for (const toml::node& c : *list) readCase(*c.as_table(), defaults, suite);
    }
    if (suite.cases.empty())
      throw InputError(file_, "no [[case]] in the suite file (see docs/regression.md)");
    return suite;
  }

 private:
  [[noreturn]] void fail(const toml::source_region& r, const std::string& message) const {
    throw InputError(
        sourceLocation(file_, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)),
        message);
  }

  int integer(const toml::node& n, const std::string& key, int lo, int hi) const {
    const auto v = n.value<std::int64_t>();
    if (!n.is_integer() || !v || *v < lo || *v > hi)
      fail(n.source(),
           "'" + key + "' must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<int>(*v);
  }

  double fraction(const toml::node& n, const std::string& key) const {
    const auto v = n.value<double>();
    if (!n.is_number() || !v || !(*v >= 0 && *v <= 1))  // nan fails both comparisons
      fail(n.source(), "'" + key + "' must be a number in 0..1" +
                           (key == "min_ssim" ? std::string(" (a mean SSIM)")
                                              : std::string(" (a share of the pixels)")));
    return *v;
  }

  std::vector<int> frames(const toml::node& node) const {
    const toml::array* a = node.as_array();
    if (a == nullptr || a->empty() || !a->is_homogeneous(toml::node_type::integer))
      fail(node.source(), "'frames' must be a list of frame numbers, e.g. [0, 30, 60]");
    std::vector<int> out;
    std::set<int> seen;
    for (const toml::node& f : *a) {
      const int frame = integer(f, "frames", 0, 10000000);
      if (!seen.insert(frame).second)
        fail(node.source(), "frame " + std::to_string(frame) + " is listed twice");
      out.push_back(frame);
    }
    return out;
  }

  // `mask = [[x, y, width, height], ...]`: pixel rectangles, left and top from 0.
  PixelMask mask(const toml::node& node) const {
    const char* form = "'mask' must be a list of rectangles [x, y, width, height] in pixels";
    const toml::array* a = node.as_array();
    if (a == nullptr) fail(node.source(), form);
    PixelMask out;
    for (const toml::node& r : *a) {
      const toml::array* v = r.as_array();
      if (v == nullptr || v->size() != 4 || !v->is_homogeneous(toml::node_type::integer))
        fail(r.source(), form);
      out.push_back({integer(*v->get(0), "mask x", 0, kMaxImageSide - 1),
                     integer(*v->get(1), "mask y", 0, kMaxImageSide - 1),
                     integer(*v->get(2), "mask width", 1, kMaxImageSide),
                     integer(*v->get(3), "mask height", 1, kMaxImageSide)});
    }
    return out;
  }

  void readCase(const toml::table& t, const DiffTolerance& defaults, Suite& suite) const {
    SuiteCase c;
    c.tolerance = defaults;
    c.where = sourceLocation(file_, static_cast<int>(t.source().begin.line));
    for (auto&& [key, node] : t) {
      const std::string k(key.str());
      if (k == "name") {
        const auto v = node.value<std::string>();
        const bool valid = node.is_string() && !v->empty() && *v != "." && *v != ".." &&
                           std::all_of(v->begin(), v->end(), [](unsigned char ch) {
                             return std::isalnum(ch) || ch == '_' || ch == '-' || ch == '.';
                           });
        if (!valid) fail(node.source(), "'name' must be a folder name (letters, digits, _ - .)");
        c.name = *v;
      } else if (k == "scene") {
        const auto v = node.value<std::string>();
        if (!node.is_string() || v->empty())
          fail(node.source(),
               "'scene' must be the path of a scene file, relative to the suite folder");
        const fs::path scene =
            fs::path(*v).is_absolute() ? fs::path(*v) : fs::path(file_).parent_path() / *v;
        std::error_code ec;
        if (!fs::is_regular_file(scene, ec))
          fail(node.source(), "scene file '" + scene.string() + "' not found");
        c.scene = scene.lexically_normal().string();
      } else if (k == "frames") {
        c.frames = frames(node);
      } else if (k == "mask") {
        c.mask = mask(node);
        c.maskWhere = sourceLocation(file_, static_cast<int>(node.source().begin.line),
                                     static_cast<int>(node.source().begin.column));
      } else if (k == "size") {
        const toml::array* a = node.as_array();
        if (a == nullptr || a->size() != 2 || !a->is_homogeneous(toml::node_type::integer))
          fail(node.source(), "'size' must be [width, height] in pixels");
        c.width = integer(*a->get(0), "size", 1, kMaxImageSide);
        c.height = integer(*a->get(1), "size", 1, kMaxImageSide);
      } else if (k == "runs") {
        c.runs = integer(node, k, 1, kMaxRuns);
      } else if (k == "threshold") {
        c.tolerance.threshold = integer(node, k, 0, 255);
      } else if (k == "max_fraction") {
        c.tolerance.maxFraction = fraction(node, k);
      } else if (k == "min_ssim") {
        c.tolerance.minSsim = fraction(node, k);
      } else {
        fail(key.source(), "unknown key '" + k +
                               "' in [[case]] (valid: name, scene, frames, size, runs, "
                               "threshold, max_fraction, min_ssim, mask)");
      }
    }
    if (c.scene.empty()) throw InputError(c.where, "[[case]] needs 'scene = \"path.toml\"'");
    if (c.frames.empty()) throw InputError(c.where, "[[case]] needs 'frames = [k, ...]'");
    if (c.name.empty()) c.name = fs::path(c.scene).stem().string();
    for (const SuiteCase& other : suite.cases)
      if (other.name == c.name)
        throw InputError(c.where, "a second case named '" + c.name + "' (the first is at " +
                                      other.where + "); give one a different 'name'");
    suite.cases.push_back(std::move(c));
  }

  std::string file_;
};

}  // namespace

Suite readSuite(const std::string& suiteFile) { return SuiteReader(suiteFile).read(); }

}  // namespace vf
