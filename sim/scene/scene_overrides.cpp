// Overrides of a loaded scene (the command line's --level, --step, --collider, run limits and
// --repair), so that every command given the same options builds the same world and checksum.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

#include "sim/core/error.h"
#include "sim/scene/scene.h"

namespace vf {

void applyLevelOverride(SceneSpec& spec, int level) {
  spec.level = level;
  for (ShapeSpec& s : spec.shapes) s.level.reset();
}

namespace {
// "0.005", or "1/120"; nothing unless finite and > 0.
std::optional<double> parseStepSeconds(const std::string& text) {
  auto parse = [](const std::string& s) -> std::optional<double> {
    if (s.empty()) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
    return v;
  };
  std::optional<double> v;
  if (const auto slash = text.find('/'); slash != std::string::npos) {
    const auto num = parse(text.substr(0, slash)), den = parse(text.substr(slash + 1));
    if (num && den && *den != 0) v = *num / *den;
  } else {
    v = parse(text);
  }
  if (v && std::isfinite(*v) && *v > 0) return v;
  return std::nullopt;
}
}  // namespace

std::optional<StepRule> parseStepRule(const std::string& text) {
  if (text == "auto") return StepRule::eq20();
  if (text == "clearance") return StepRule::clearance();
  if (const auto v = parseStepSeconds(text)) return StepRule::fixed(*v);
  return std::nullopt;
}

std::string stepRuleChoices() {
  return "\"auto\" (eq. 20), \"clearance\" (eq. 17 only where a body could touch something "
         "within the step) or a fixed step in seconds > 0, e.g. 0.005 or \"1/120\"";
}

std::string checkStepOption(const std::string& text) {
  if (parseStepRule(text)) return "";
  return "expected " + stepRuleChoices() + ", got '" + text + "'";
}

void applyStepOverride(SceneSpec& spec, const std::string& text) {
  const auto rule = parseStepRule(text);
  if (!rule) throw InputError("", "--step: " + checkStepOption(text));
  spec.step = *rule;
}

void applyColliderOverride(SceneSpec& spec, const std::string& method) {
  if (method != "voxel" && method != "polygon")
    throw InputError("", "--collider: expected 'voxel' or 'polygon', got '" + method + "'");
  spec.collider = method == "polygon" ? ColliderMethod::kPolygon : ColliderMethod::kVoxel;
}

void applyOverrides(SceneSpec& spec, const SceneOverrides& o) {
  if (o.level) applyLevelOverride(spec, *o.level);
  if (!o.step.empty()) applyStepOverride(spec, o.step);
  if (!o.collider.empty()) applyColliderOverride(spec, o.collider);
  if (o.maxSteps) spec.limits.maxSteps = *o.maxSteps;
  if (o.maxSpeed) spec.limits.maxSpeed = *o.maxSpeed;
  if (o.repair)
    for (ShapeSpec& s : spec.shapes) s.repair = true;
  if (o.threads) spec.threads = *o.threads;
}

}  // namespace vf
