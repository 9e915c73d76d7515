// Scene files (TOML) -> SceneSpec: the parse, the order of the tables and the checks that span
// them. The tables' readers live beside it (scene_reader.h lists them); together they are the
// only files in voxfall that include toml++.
//
// Every value goes through a Reader that knows the file name, so each problem becomes one
// InputError at "file:line:column" of the offending key or value, saying what is wrong and what
// would be valid. Unknown keys are errors, never ignored: a typo such as `restitutoin` must not
// silently fall back to a default, so the nearest valid key is suggested by edit distance.
// Errors are reported in file order within a table, so the first problem a reader would meet is
// the one shown.
#include <toml++/toml.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>

#include "sim/core/error.h"
#include "sim/scene/scene.h"
#include "sim/scene/scene_keys.h"
#include "sim/scene/scene_reader.h"

namespace vf {
namespace scene_reading {

// --- [simulation] -------------------------------------------------------------------------

namespace {

// [simulation] rest: the speed and time under which a rock counts as at rest.
void readRest(const Reader& r, const toml::node& n, RestCriterion& rest) {
  const toml::table& rt = r.table(n, "rest");
  r.checkKeys(rt, sceneKeysOf("simulation.rest"), "[simulation] rest");
  if (const auto* x = rt.get("speed")) rest.speed = r.positive(*x, "rest.speed", " m/s");
  if (const auto* x = rt.get("time")) rest.time = r.nonNegative(*x, "rest.time", " s");
}

// [simulation] step: a rule's name, as --step takes it, or a fixed step in seconds.
StepRule readStepRule(const Reader& r, const toml::node& n) {
  const std::string valid = "'step' must be " + stepRuleChoices();
  if (const auto* s = n.as_string()) {  // the text --step takes
    const auto rule = parseStepRule(s->get());
    if (!rule) r.fail(n, valid + ", got \"" + s->get() + "\"");
    return *rule;
  }
  if (!n.is_number()) r.fail(n, valid + ", got " + typeName(n));
  const double v = r.number(n, "step");
  if (!(v > 0)) r.fail(n, valid + ", got " + formatNumber(v));
  return StepRule::fixed(v);
}

// [simulation] collider: "voxel" or "polygon".
ColliderMethod readCollider(const Reader& r, const toml::node& n) {
  const std::string c = r.string(n, "collider");
  if (c == "voxel") return ColliderMethod::kVoxel;
  if (c != "polygon")
    r.fail(n,
           "'collider' must be \"voxel\" (sphere trees) or \"polygon\" (the paper's "
           "comparison method, convex meshes only), got \"" +
               c + "\"");
  return ColliderMethod::kPolygon;
}

}  // namespace

void readSimulation(const Reader& r, const toml::table& t, SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("simulation"), "[simulation]");
  if (const auto* n = t.get("rotation")) {
    const std::string v = r.string(*n, "rotation");
    if (v != "euler" && v != "midpoint")
      r.fail(*n,
             "'rotation' must be \"euler\" (the paper's explicit Euler) or \"midpoint\" (keeps "
             "the energy of free tumbling; the default with ground materials), got \"" +
                 v + "\"");
    spec.rotation = v == "midpoint" ? RotationUpdate::kMidpoint : RotationUpdate::kExplicitEuler;
  }
  if (const auto* n = t.get("stop")) {
    const std::string v = r.string(*n, "stop");
    if (v != "duration" && v != "all_at_rest")
      r.fail(*n,
             "'stop' must be \"duration\" (the default) or \"all_at_rest\" (every rock "
             "stopped or gone), got \"" +
                 v + "\"");
    spec.stopWhenSettled = v == "all_at_rest";
  }
  if (const auto* n = t.get("rest")) readRest(r, *n, spec.rest);
  if (const auto* n = t.get("duration")) spec.duration = r.positive(*n, "duration", " s");
  if (const auto* n = t.get("level"))
    spec.level = static_cast<int>(r.integerInRange(*n, "level", kMinLevel, kMaxLevel));
  if (const auto* n = t.get("step")) spec.step = readStepRule(r, *n);
  if (const auto* n = t.get("gravity")) spec.gravity = r.vec3(*n, "gravity");
  if (const auto* n = t.get("fps")) spec.fps = r.positive(*n, "fps", " frames per second");
  if (const auto* n = t.get("collider")) spec.collider = readCollider(r, *n);
  if (const auto* n = t.get("method")) {
    const std::string m = r.string(*n, "method");
    if (m != "fast" && m != "paper")
      r.fail(*n,
             "'method' must be \"fast\" (contact reduction and sleeping, the default) or "
             "\"paper\" (the paper's method: neither), got \"" +
                 m + "\"");
    spec.contactReduction = spec.sleep = m == "fast";
  }
  // Each key overrides the method's choice.
  if (const auto* n = t.get("contact_reduction"))
    spec.contactReduction = r.boolean(*n, "contact_reduction");
  if (const auto* n = t.get("sleep")) spec.sleep = r.boolean(*n, "sleep");
  // Runaway limits (sim/run_guard.h).
  if (const auto* n = t.get("max_steps"))
    spec.limits.maxSteps = static_cast<std::uint64_t>(
        r.integerInRange(*n, "max_steps", 1, std::numeric_limits<std::int64_t>::max()));
  if (const auto* n = t.get("max_speed"))
    spec.limits.maxSpeed = r.positive(*n, "max_speed", " m/s");
}

// --- [contact] ----------------------------------------------------------------------------

void readContact(const Reader& r, const toml::table& t, ContactMaterial& c) {
  r.checkKeys(t, sceneKeysOf("contact"), "[contact]");
  if (const auto* n = t.get("restitution")) {
    const toml::table& e = r.table(*n, "restitution");
    r.checkKeys(e, sceneKeysOf("contact.restitution"), "[contact] restitution");
    if (const auto* v = e.get("body_body"))
      c.restitutionBodyBody = r.inRange(*v, "restitution.body_body", 0, 1);
    if (const auto* v = e.get("body_ground"))
      c.restitutionBodyGround = r.inRange(*v, "restitution.body_ground", 0, 1);
  }
  if (const auto* n = t.get("friction")) {
    const toml::table& f = r.table(*n, "friction");
    r.checkKeys(f, sceneKeysOf("contact.friction"), "[contact] friction");
    if (const auto* v = f.get("body_body"))
      c.frictionBodyBody = r.nonNegative(*v, "friction.body_body", " (Coulomb coefficient)");
    if (const auto* v = f.get("body_ground"))
      c.frictionBodyGround = r.nonNegative(*v, "friction.body_ground", " (Coulomb coefficient)");
  }
}

}  // namespace scene_reading

using namespace scene_reading;

namespace {

// The scene file parsed; throws InputError when it is missing, not a file or not TOML.
toml::table parseSceneFile(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "scene file not found");
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "scene path is not a file");
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(sourceLocation(path, static_cast<int>(b.line), static_cast<int>(b.column)),
                     "TOML syntax error: " + std::string(e.description()));
  }
}

// The frames a scene asks for, simulated and drawn, within what a run can allocate.
void checkFrameCounts(const Reader& r, const toml::table& root, const SceneSpec& spec) {
  // Frame k is at k / fps for k = 0 .. floor(duration * fps): keep that count allocatable.
  if (spec.duration * spec.fps > kMaxSceneFrames) {
    const toml::node* n = root.at_path("simulation.duration").node();
    throw InputError(n != nullptr ? r.where(*n) : spec.path,
                     "duration * fps = " + formatNumber(spec.duration * spec.fps) +
                         " frames; at most " + formatNumber(kMaxSceneFrames) + " are supported");
  }
  // Drawn frames: duration * fps / speed (slow motion makes more).
  if (spec.duration * spec.fps / spec.output.speed > kMaxSceneFrames) {
    const toml::node* n = root.at_path("output.speed").node();
    throw InputError(
        n != nullptr ? r.where(*n) : spec.path,
        "duration * fps / speed = " + formatNumber(spec.duration * spec.fps / spec.output.speed) +
            " frames; at most " + formatNumber(kMaxSceneFrames) + " are supported");
  }
}

}  // namespace

SceneSpec loadScene(const std::string& path) {
  SceneSpec spec;
  spec.path = path;
  spec.name = fs::path(path).stem().string();

  const toml::table root = parseSceneFile(path);
  const Reader r(path);
  r.checkKeys(root, sceneKeysOf(""), "the scene's top level");
  const fs::path sceneFolder = fs::path(path).parent_path();

  // Shapes before bodies and emitters (which name them); bodies and emitters before the camera
  // (whose `follow` is a body index).
  if (const auto* n = root.get("simulation")) readSimulation(r, r.table(*n, "simulation"), spec);
  if (const auto* n = root.get("contact")) readContact(r, r.table(*n, "contact"), spec.contact);
  if (const auto* n = root.get("ground")) readGround(r, r.table(*n, "ground"), sceneFolder, spec);
  if (const auto* n = root.get("forest")) readForest(r, r.table(*n, "forest"), sceneFolder, spec);
  if (const auto* n = root.get("light")) readLight(r, r.table(*n, "light"), spec);
  // A rock-fall scene (one with ground materials) rotates by the midpoint rule unless it says
  // otherwise: the paper's explicit Euler gains energy in free tumbling, and a rock's runout
  // depends on the spin it keeps in flight. Scenes without materials keep the paper's update.
  if (!spec.groundMaterial.empty() && root.at_path("simulation.rotation").node() == nullptr)
    spec.rotation = RotationUpdate::kMidpoint;
  if (const auto* n = root.get("shapes")) readShapes(r, r.table(*n, "shapes"), sceneFolder, spec);
  if (const auto* n = root.get("bodies")) readBodies(r, arrayOfTables(r, *n, "bodies"), spec);
  if (const auto* n = root.get("emitters")) readEmitters(r, arrayOfTables(r, *n, "emitters"), spec);
  if (const auto* n = root.get("camera"))
    spec.camera = readCamera(r, r.table(*n, "camera"), "camera", "[camera]", spec);
  if (const auto* n = root.get("cameras")) readCameras(r, r.table(*n, "cameras"), spec);
  if (const auto* n = root.get("output")) readOutput(r, r.table(*n, "output"), spec);
  if (const auto* n = root.get("ensemble"))
    readEnsemble(r, r.table(*n, "ensemble"), sceneFolder, spec);
  if (const auto* n = root.get("evaluation_lines"))
    readEvaluationLines(r, arrayOfTables(r, *n, "evaluation_lines"), sceneFolder, spec);
  if (const auto* n = root.get("barriers"))
    readBarriers(r, arrayOfTables(r, *n, "barriers"), sceneFolder, spec);
  checkFrameCounts(r, root, spec);
  return spec;
}

std::string frameSideProblem(const std::string& side, std::int64_t pixels) {
  if (pixels >= 1 && pixels <= kMaxImageSide) return "";
  return "the frame " + side + " must be 1.." + std::to_string(kMaxImageSide) + " pixels, got " +
         std::to_string(pixels);
}

void selectCamera(SceneSpec& spec, const std::string& name) {
  if (name == "camera") return;  // [camera], or the automatic camera without one
  std::string names = "camera";
  for (const CameraSpec& c : spec.cameras) {
    if (c.name == name) {
      spec.camera = c;
      return;
    }
    names += ", " + c.name;
  }
  throw InputError(spec.path, "no camera named '" + name + "'; the scene has: " + names);
}

}  // namespace vf
