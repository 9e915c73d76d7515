// Options shared by the voxfall subcommands, parsed in one place each.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vf {
struct SceneOverrides;
struct OverlayChoice;  // render/run/run_input.h
}  // namespace vf

namespace CLI {
class App;
class Validator;
}  // namespace CLI

namespace vf::cli {

// A check for a number option: its text read whole as a finite number from lo to hi. CLI11's
// own Range lets "nan" through (every comparison with it is false).
CLI::Validator finiteNumberIn(double lo, double hi);

// A check for an integer option: its text read whole as an integer from lo to hi (no sign, no
// clamping: CLI11's conversion takes "-1" for an unsigned option as 2^64 - 1).
CLI::Validator integerIn(std::uint64_t lo, std::uint64_t hi);

// -y (overwrite existing outputs) and -n (never overwrite, exit instead), ffmpeg's flags.
void addOverwriteFlags(CLI::App& command, bool& overwrite, bool& neverOverwrite);
// --extent XMIN,YMIN,XMAX,YMAX of an ensemble's maps (ensemble, ensemble-merge).
void addMapExtentOption(CLI::App& command, std::vector<double>& extent);

// --level N, --step S|auto|clearance, --collider voxel|polygon, --max-steps N, --max-speed V and
// --repair (sim/scene/scene.h's SceneOverrides), for the commands that simulate; `what` ends
// their help ("" or e.g. " (scenes only)").
void addPhysicsOptions(CLI::App& command, SceneOverrides& overrides, const std::string& what = "");

// --threads N for the commands that step one scene (SceneOverrides::threads; an ensemble runs
// one realisation per thread instead, --jobs).
void addThreadsOption(CLI::App& command, SceneOverrides& overrides, const std::string& what = "");

// A frame size "WxH" (the x may be capital): width and height in pixels as written; nothing
// for anything else ("640x", "640x480x2", "640 x 480"). The range is checked by addSizeOption.
std::optional<std::pair<std::int64_t, std::int64_t>> parseSize(const std::string& text);
// --size WxH, parsed once, here: a malformed size, or a side outside frameSideProblem's range
// (sim/scene/scene.h, the rule of a scene's [output]), is a usage error (exit 2). Evenness is
// the MP4 encoder's check alone.
void addSizeOption(CLI::App& command, std::optional<std::pair<int, int>>& size);

// --speed X: simulated seconds per second of video, overriding [output] speed (0.25: four
// times slower, 10: a time-lapse).
void addSpeedOption(CLI::App& command, std::optional<double>& speed);

// "time", "scale", "time,scale" (any order) or "none"; nothing for anything else.
std::optional<OverlayChoice> parseOverlay(const std::string& text);
// --alpha (a transparent background, PNG only) and --overlay LIST, overriding [output] alpha
// and overlay; a malformed list is a usage error.
void addFrameLookOptions(CLI::App& command, bool& alpha, std::optional<OverlayChoice>& overlay);

}  // namespace vf::cli
