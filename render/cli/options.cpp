#include "render/cli/options.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "sim/scene/scene.h"
#include "sim/shape/sphere_tree.h"

namespace vf::cli {

void addOverwriteFlags(CLI::App& command, bool& overwrite, bool& neverOverwrite) {
  CLI::Option* yes =
      command.add_flag("-y", overwrite, "overwrite outputs that exist (never an input of the run)");
  CLI::Option* no =
      command.add_flag("-n", neverOverwrite, "never overwrite: exit if an output exists");
  yes->excludes(no);
}

namespace {

// `text` read whole as a finite number; nothing for anything else ("nan", "inf", "1e400", "5x").
std::optional<double> readFinite(const std::string& text) {
  double v = 0;
  const char* end = text.data() + text.size();
  const auto [at, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || at != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

// The limits take what the scene's [simulation] keys take (scene_loader.cpp), read whole:
// CLI11's own conversion clamped 2^64 and more to the largest count, and its positive-number
// check let "nan" through and answered "inf" with a 309-digit range.
std::string checkMaxStepsOption(std::string& text) {
  std::int64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [at, ec] = std::from_chars(text.data(), end, v);
  if (ec == std::errc() && at == end && v >= 1) return "";
  return "must be an integer from 1 to 9223372036854775807, got " + text;
}

std::string checkMaxSpeedOption(std::string& text) {
  const std::optional<double> v = readFinite(text);
  return v && *v > 0 ? "" : "must be a finite number > 0 (m/s), got " + text;
}

}  // namespace

CLI::Validator finiteNumberIn(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const std::optional<double> v = readFinite(text);
        if (v && *v >= lo && *v <= hi) return "";
        char range[64];
        std::snprintf(range, sizeof range, "%g to %g", lo, hi);
        return std::string("must be a number from ") + range + ", got " + text;
      },
      "", "FINITE_RANGE");
}

void addPhysicsOptions(CLI::App& command, SceneOverrides& o, const std::string& what) {
  command
      .add_option("--level", o.level,
                  "voxel level Lv for every shape (overrides the scene's levels)" + what)
      ->type_name("N")
      ->check(CLI::Range(kMinLevel, kMaxLevel));
  command
      .add_option("--step", o.step,
                  "time step: 'auto' (eq. 20), 'clearance' (eq. 17 only where a body could "
                  "touch something within the step) or seconds, e.g. 0.005 or 1/120 (overrides "
                  "the scene)" +
                      what)
      ->check(CLI::Validator([](std::string& text) { return checkStepOption(text); }, "", "STEP"))
      ->type_name("S|auto|clearance");
  command
      .add_option("--collider", o.collider,
                  "contact method: voxel (sphere trees) or polygon (the paper's comparison "
                  "method, convex meshes only); overrides the scene" +
                      what)
      ->check(CLI::IsMember({"voxel", "polygon"}))
      ->type_name("voxel|polygon");
  command
      .add_option("--max-steps", o.maxSteps,
                  "refuse runs needing more steps than this (default 10000000)" + what)
      ->type_name("N")
      ->check(CLI::Validator(checkMaxStepsOption, "", "MAX_STEPS"));
  command
      .add_option("--max-speed", o.maxSpeed,
                  "stop the run when a body moves faster than this, m/s (default 1000)" + what)
      ->type_name("V")
      ->check(CLI::Validator(checkMaxSpeedOption, "", "MAX_SPEED"));
  command.add_flag("--repair", o.repair,
                   "repair every shape's mesh: fill small holes, remove duplicate and degenerate "
                   "triangles, fix the winding" +
                       what);
}

void addThreadsOption(CLI::App& command, SceneOverrides& o, const std::string& what) {
  command
      .add_option("--threads", o.threads,
                  "threads for finding and solving contacts (default 1; the results are the "
                  "same bits for any count; pays with hundreds of bodies in contact)" +
                      what)
      ->type_name("N")
      ->check(CLI::Range(1, 256));
}

std::optional<std::pair<std::int64_t, std::int64_t>> parseSize(const std::string& text) {
  const std::size_t x = text.find_first_of("xX");
  if (x == std::string::npos) return std::nullopt;
  const auto side = [](const char* begin, const char* end) -> std::optional<std::int64_t> {
    std::int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(begin, end, v);
    if (ec != std::errc() || ptr != end || begin == end) return std::nullopt;
    return v;
  };
  const auto w = side(text.data(), text.data() + x);
  const auto h = side(text.data() + x + 1, text.data() + text.size());
  if (!w || !h) return std::nullopt;
  return std::make_pair(*w, *h);
}

void addSizeOption(CLI::App& command, std::optional<std::pair<int, int>>& size) {
  command
      .add_option_function<std::string>(
          "--size",
          [&size](const std::string& text) {
            const auto parsed = parseSize(text);
            if (!parsed)
              throw CLI::ValidationError("--size",
                                         "'" + text + "' is not WxH in pixels, e.g. 1280x720");
            // The limit is the scene's [output] one, in the same words (frameSideProblem).
            for (const auto& [name, pixels] :
                 {std::pair<const char*, std::int64_t>{"width", parsed->first},
                  {"height", parsed->second}}) {
              const std::string problem = frameSideProblem(name, pixels);
              if (!problem.empty()) throw CLI::ValidationError("--size", problem);
            }
            size =
                std::make_pair(static_cast<int>(parsed->first), static_cast<int>(parsed->second));
          },
          "frame size in pixels, e.g. 1280x720 (default: the scene's [output] size)")
      ->type_name("WxH");
}

}  // namespace vf::cli
