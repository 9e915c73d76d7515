#include "render/run/run_report.h"

#include <cinttypes>
#include <cmath>

#include "render/output/number_text.h"
#include "render/output/output_file.h"
#include "sim/core/error.h"

namespace vf {

// The build may pass the project version; this fallback must match project() in CMakeLists.txt.
#ifndef VOXFALL_VERSION
#define VOXFALL_VERSION "0.1.0"
#endif

const char* voxfallVersion() { return VOXFALL_VERSION; }

// --- CSV ------------------------------------------------------------------------------------

void writeCsvHeader(std::FILE* out) {
  std::fputs("frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", out);
}

void writeCsvFrame(std::FILE* out, int frame, double time, const World& world,
                   const std::vector<BodyState>& states, const std::vector<char>& active) {
  for (int id = 0; id < world.bodyCount(); ++id) {
    if (!active[static_cast<std::size_t>(id)]) continue;
    const BodyState& s = states[static_cast<std::size_t>(id)];
    const Vec3 v = world.velocity(id, s);
    const Vec3 w = world.angularVelocity(id, s);
    std::fputs(csvRow(frame, time, id, s.x.x(), s.x.y(), s.x.z(), s.q.w(), s.q.x(), s.q.y(),
                      s.q.z(), v.x(), v.y(), v.z(), w.x(), w.y(), w.z())
                   .c_str(),
               out);
  }
}

// --- JSON and human summary -----------------------------------------------------------------

namespace {

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// JSON has no inf or nan; null says "no meaningful value" without breaking parsers.
std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  return numberText(v);
}

std::string jsonCount(std::uint64_t v) { return std::to_string(v); }

}  // namespace

// null, or the signal that stopped the run and how far it got.
std::string interruptionJson(const RunInterruption& i, int frames) {
  if (i.signal == 0) return "null";
  return "{\"signal\": " + jsonString(signalName(i.signal)) + ", \"time\": " + jsonNumber(i.time) +
         ", \"frames\": " + std::to_string(frames) + "}";
}

void writeSummaryJson(std::FILE* out, const std::string& scene, const RunSummary& s,
                      const RunInterruption& interruption) {
  const std::pair<const char*, std::string> fields[] = {
      {"scene", jsonString(scene)},
      {"frames", std::to_string(s.frames)},
      {"steps", jsonCount(s.totals.steps)},
      {"dt_min", jsonNumber(s.totals.dtMin)},
      {"dt_max", jsonNumber(s.totals.dtMax)},
      {"wall_seconds", jsonNumber(s.wallSeconds)},
      {"sphere_tests", jsonCount(s.totals.sphereTests)},
      {"contacts", jsonCount(s.totals.contacts)},
      {"max_penetration_body_body", jsonNumber(s.maxPenetrationBodyBody)},
      {"max_penetration_body_ground", jsonNumber(s.maxPenetrationBodyGround)},
      {"tunnelled", std::to_string(s.tunnelled)},
      {"kinetic_energy", jsonNumber(s.kineticEnergy)},
      {"potential_energy", jsonNumber(s.potentialEnergy)},
      {"checksum", jsonString(s.checksumHex())},
      {"warnings", "{\"overlapping_releases\": " + jsonCount(s.totals.overlappingReleases) +
                       ", \"frozen_non_finite\": " + jsonCount(s.totals.nonFinite) +
                       ", \"floored_steps\": " + jsonCount(s.totals.floored) + "}"},
      {"interrupted", interruptionJson(interruption, s.frames)},
  };
  std::fputs("{\n", out);
  const std::size_t n = sizeof fields / sizeof fields[0];
  for (std::size_t i = 0; i < n; ++i)
    std::fprintf(out, "  \"%s\": %s%s\n", fields[i].first, fields[i].second.c_str(),
                 i + 1 < n ? "," : "");
  std::fputs("}\n", out);
}

void printSummary(std::FILE* out, const std::string& scene, const RunSummary& s) {
  std::fprintf(out, "%s: %d frames, %" PRIu64 " steps (dt %.3g .. %.3g s), %.2f s wall\n",
               scene.c_str(), s.frames, s.totals.steps, s.totals.dtMin, s.totals.dtMax,
               s.wallSeconds);
  std::fprintf(out, "  sphere tests %" PRIu64 ", contacts %" PRIu64 "\n", s.totals.sphereTests,
               s.totals.contacts);
  std::fprintf(out, "  max penetration: body-body %.3g m, body-ground %.3g m; tunnelled %d\n",
               s.maxPenetrationBodyBody, s.maxPenetrationBodyGround, s.tunnelled);
  std::fprintf(out, "  final energy: kinetic %.6g J, potential %.6g J\n", s.kineticEnergy,
               s.potentialEnergy);
  std::fprintf(out, "  checksum %s\n", s.checksumHex().c_str());
  // Things that explain surprising results; silent when all is well.
  if (s.totals.overlappingReleases > 0)
    std::fprintf(out,
                 "  warning: %" PRIu64
                 " bodies were released overlapping another body "
                 "(an emitter aimed into a pile?); their interpenetration is not the step's\n",
                 s.totals.overlappingReleases);
  if (s.totals.nonFinite > 0)
    std::fprintf(out,
                 "  warning: %" PRIu64 " times a body's state went non-finite and it was frozen\n",
                 s.totals.nonFinite);
  if (s.totals.floored > 0)
    std::fprintf(out,
                 "  warning: %" PRIu64
                 " steps were held at the minimum step (a body moved faster "
                 "than 1e4 m/s)\n",
                 s.totals.floored);
}

}  // namespace vf
