#include "render/run/lines_output.h"

#include <cmath>
#include <cstdio>

#include "render/maps/line_plots.h"
#include "render/output/number_text.h"

namespace vf {
namespace {

// %.17g, or nothing for NaN (an empty CSV field).
// A number in its shortest exact text (number_text.h), so that a capacity given as 0.05 kJ
// reads 0.05; NaN: an empty field.
void field(std::FILE* out, double v, const char* after = ",") {
  std::fprintf(out, "%s%s", std::isnan(v) ? "" : numberText(v).c_str(), after);
}

// A name as one CSV field: quoted, with quotes doubled.
std::string csvText(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

void writeCrossingsCsv(std::FILE* out, const std::vector<EvaluationLine>& lines,
                       const std::vector<LineCrossing>& crossings, const Vec3& shift) {
  std::fprintf(out,
               "line,name,rock,time,x,y,z,vx,vy,vz,speed,energy_translational_kj,"
               "energy_rotational_kj,energy_kj,height,direction\n");
  for (const LineCrossing& c : crossings) {
    std::fprintf(out, "%d,%s,%lld,", c.line, csvText(lines[c.line].name).c_str(),
                 static_cast<long long>(c.rock));
    field(out, c.time);
    const Vec3 p = c.point - shift;
    for (double v :
         {p.x(), p.y(), p.z(), c.velocity.x(), c.velocity.y(), c.velocity.z(), c.velocity.norm(),
          c.translationalEnergy / 1000, c.rotationalEnergy / 1000, c.energy() / 1000, c.height})
      field(out, v);
    std::fprintf(out, "%d\n", c.direction);
  }
}

void writeLinesCsv(std::FILE* out, const std::vector<LineSummary>& summaries) {
  std::fprintf(out,
               "line,name,crossings,rocks_crossing,rocks,probability,energy_p50_kj,energy_p95_kj,"
               "energy_p99_kj,height_p50,height_p95,height_p99\n");
  for (std::size_t l = 0; l < summaries.size(); ++l) {
    const LineSummary& s = summaries[l];
    std::fprintf(out, "%zu,%s,%lld,%lld,%lld,", l, csvText(s.name).c_str(),
                 static_cast<long long>(s.crossings), static_cast<long long>(s.rocksCrossing),
                 static_cast<long long>(s.rocks));
    field(out, s.probability);
    for (double e : s.energy) field(out, e / 1000);
    for (std::size_t k = 0; k < s.height.size(); ++k)
      field(out, s.height[k], k + 1 < s.height.size() ? "," : "\n");
  }
}

void writeBarriersCsv(std::FILE* out, const std::vector<Barrier>& barriers,
                      const std::vector<BarrierResult>& results,
                      const std::vector<std::int64_t>& failures) {
  std::fprintf(out, "barrier,name,capacity_kj,hits,stopped,passed,max_energy_kj,failed\n");
  for (std::size_t b = 0; b < barriers.size(); ++b) {
    const BarrierResult& r = results[b];
    std::fprintf(out, "%zu,%s,", b, csvText(barriers[b].name).c_str());
    field(out, barriers[b].capacity / 1000);
    std::fprintf(out, "%lld,%lld,%lld,", static_cast<long long>(r.hits),
                 static_cast<long long>(r.stopped), static_cast<long long>(r.passed));
    field(out, r.hits > 0 ? r.maxEnergy / 1000 : NAN);
    std::fprintf(out, "%lld\n", static_cast<long long>(failures[b]));
  }
}

LineFiles::LineFiles(const std::filesystem::path& dir, const OutputRules& rules, bool plots)
    : dir_(dir), rules_(rules), plots_(plots) {
  crossings_ = std::make_unique<OutputFile>((dir / "crossings.csv").string(), rules);
  summary_ = std::make_unique<OutputFile>((dir / "lines.csv").string(), rules);
  if (plots) {
    checkOutputPath((dir / "lines.png").string(), rules);
    checkOutputPath((dir / "lines_profile.png").string(), rules);
  }
}

LineFiles::~LineFiles() = default;

std::string LineFiles::write(const std::vector<EvaluationLine>& lines,
                             const std::vector<LineCrossing>& crossings, std::int64_t rocks,
                             const Vec3& shift) {
  const std::vector<LineSummary> summaries = summariseLines(lines, crossings, rocks);
  writeCrossingsCsv(crossings_->stream(), lines, crossings, shift);
  writeLinesCsv(summary_->stream(), summaries);
  std::string written = "crossings.csv, lines.csv";
  if (plots_) {
    writeLineHistograms(lines, summaries, crossings, (dir_ / "lines.png").string(), rules_);
    writeLineProfiles(lines, crossings, (dir_ / "lines_profile.png").string(), rules_);
    written += ", lines.png, lines_profile.png";
  }
  // The tables last: a failed plot leaves no table that passes for a complete output.
  crossings_->commit();
  summary_->commit();
  return written;
}

}  // namespace vf
