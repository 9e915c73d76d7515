#include "render/cli/options.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "render/run/run_input.h"
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

void addMapExtentOption(CLI::App& command, std::vector<double>& extent) {
  command
      .add_option("--extent", extent,
                  "with --maps: the maps' extent in the DEM file's coordinates, m (default: the "
                  "reached area and the release areas with a margin)")
      ->delimiter(',')
      ->expected(4)
      ->type_name("XMIN,YMIN,XMAX,YMAX");
}

namespace {

// [begin, end) read whole as a T by from_chars; nothing for anything else (an empty text, "5x",
// "-1" as an unsigned type, a value past T's range; CLI11's own conversion clamped those).
template <class T>
std::optional<T> readWhole(const char* begin, const char* end) {
  T v{};
  const auto [at, ec] = std::from_chars(begin, end, v);
  if (ec != std::errc() || at != end || begin == end) return std::nullopt;
  return v;
}
template <class T>
std::optional<T> readWhole(const std::string& text) {
  return readWhole<T>(text.data(), text.data() + text.size());
}

// `text` read whole as a finite number ("nan", "inf", "1e400" are not).
std::optional<double> readFinite(const std::string& text) {
  const std::optional<double> v = readWhole<double>(text);
  return v && std::isfinite(*v) ? v : std::nullopt;
}

// The speed limit takes what the scene's max_speed takes: CLI11's positive-number check let
// "nan" through and answered "inf" with a 309-digit range.
std::string checkMaxSpeedOption(std::string& text) {
  const std::optional<double> v = readFinite(text);
  return v && *v > 0 ? "" : "must be a finite number > 0 (m/s), got " + text;
}

}  // namespace

CLI::Validator integerIn(std::uint64_t lo, std::uint64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const std::optional<std::uint64_t> v = readWhole<std::uint64_t>(text);
        if (v && *v >= lo && *v <= hi) return "";
        return "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi) +
               ", got " + text;
      },
      "", "INTEGER_RANGE");
}

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
      // What [simulation] max_steps takes (CLI11's conversion clamped 2^64 and more).
      ->check(integerIn(1, std::numeric_limits<std::int64_t>::max()));
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
  const auto w = readWhole<std::int64_t>(text.data(), text.data() + x);
  const auto h = readWhole<std::int64_t>(text.data() + x + 1, text.data() + text.size());
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

void addSpeedOption(CLI::App& command, std::optional<double>& speed) {
  command
      .add_option("--speed", speed,
                  "simulated seconds per second of video: 0.25 is slow motion, 10 a time-lapse "
                  "(overrides [output] speed; frame k shows t = k speed / fps)")
      ->check(finiteNumberIn(1e-3, 1e6))
      ->type_name("X");
}

std::optional<OverlayChoice> parseOverlay(const std::string& text) {
  OverlayChoice choice;
  if (text == "none") return choice;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    bool& flag = item == "time" ? choice.time : choice.scale;
    if ((item != "time" && item != "scale") || flag) return std::nullopt;
    flag = true;
    if (comma == std::string::npos) return choice;
    start = comma + 1;
  }
}

void addFrameLookOptions(CLI::App& command, bool& alpha, std::optional<OverlayChoice>& overlay) {
  command.add_flag("--alpha", alpha,
                   "transparent background (PNG only): sky and floor clear, bodies, terrain and "
                   "the shadows on the floor kept (overrides [output] alpha)");
  command
      .add_option_function<std::string>(
          "--overlay",
          [&overlay](const std::string& text) {
            overlay = parseOverlay(text);
            if (!overlay)
              throw CLI::ValidationError(
                  "--overlay", "'" + text + "' is not a list of time and scale, e.g. time,scale");
          },
          "draw the simulated time and/or a scale bar on the frames: time, scale, time,scale "
          "or none (overrides [output] overlay)")
      ->type_name("LIST");
}

}  // namespace vf::cli
