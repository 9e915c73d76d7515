// Ground-material presets and the class-raster lookup.
//
// Why the STONE table: of the published per-substrate parameter sets surveyed
// (shared/rockfall-models.md), it is the only one that gives a rolling coefficient per
// substrate. RAMMS::ROCKFALL's terrain categories, Rockyfor3D's Rn per soil type and the CRSP
// and RocFall material tables could not be read with numbers, and the DEM codes (Chrono,
// LIGGGHTS, Rockable) give no rock-on-soil values. Rolling resistance is the contact law
// chosen because it is the one that removes energy from a rock rolling without slip (Coulomb
// friction of any mu does no work there), and without it rocks on a terrain run out too far.
//
// Values: the r.stone manual (OSGeo grass-addons src/raster/r.stone/r.stone.md, commit
// 20493ad28ded), "extracted from" Guzzetti, Crosta, Detti & Agliardi 2002, STONE,
// Computers & Geosciences 28(9):1079-1093: rolling friction (tan of the rolling friction
// angle), normal restitution Rn and tangential restitution Rt (percent, here as fractions);
// how a rigid body uses them: sim/solve/ground_law.cpp.
// STONE is a lumped-mass model: its rolling friction decelerates a point at mu g cos(theta);
// here it is a torque on a rigid body (Azzoni et al. 1995's form), which for a sphere gives
// 5/7 of that deceleration and the same critical slope atan(mu_r).
//
// The slip-law presets are the two published parameter sets of the RAMMS-type law
// (shared/rockfall-models.md sections 1 and 9.3); docs/rockfall.md lists what each source
// prints and what voxfall adds.
#include "sim/ground/ground_material.h"

#include <cmath>
#include <numbers>

#include "sim/ground/ground_variability.h"

namespace vf {
namespace {

struct Preset {
  const char* name;
  double rolling;      // STONE rolling friction coefficient
  double restitution;  // STONE Rn / 100
  double tangential;   // STONE Rt / 100
  const char* stoneClass;
};

constexpr const char* kStone =
    "Guzzetti et al. 2002 (STONE), per-lithology table as quoted by the GRASS r.stone manual";

// A subset of the STONE classes with names a scene writer reaches for; every number is the
// table's (rockfall-models.md section 4).
constexpr Preset kPresets[] = {
    {"colluvial", 0.80, 0.15, 0.40, "Alluvial, lacustrine, marine, eluvial and colluvial deposits"},
    {"glacial_deposits", 0.65, 0.35, 0.55, "Glacial deposits"},
    {"landslide_deposits", 0.65, 0.35, 0.55, "Landslides"},
    {"anthropic_deposits", 0.65, 0.35, 0.55, "Anthropic deposits"},
    {"loose_clastic", 0.35, 0.45, 0.55, "Loosely packed clastic deposits"},
    {"consolidated_clastic", 0.40, 0.55, 0.65, "Consolidated clastic deposits"},
    {"marl", 0.40, 0.55, 0.65, "Marl"},
    {"flysch", 0.40, 0.55, 0.65, "Flysch"},
    {"schists", 0.35, 0.60, 0.70, "Schists"},
    {"carbonate_rock", 0.30, 0.65, 0.75, "Carbonate rocks"},
    {"igneous_rock", 0.30, 0.65, 0.75, "Intrusive igneous rocks"},
    {"bedrock", 0.30, 0.65, 0.75, "Non-schists"},
    {"lakes_glaciers", 0.95, 0.10, 0.10, "Lakes, glaciers"},
};

// A scar layer's numbers (sim/solve/scar_drag.cpp): all zero for none.
struct ScarPreset {
  double density;     // rho_Sigma, kg/m^3
  double fluidDrag;   // C_f
  double compaction;  // C_s
  double modulus;     // M_e, MN/m^2
};

struct SlipPreset {
  const char* name;
  double muMin, muMax, kappa, beta;  // kappa 1/m, beta 1/s
  double restitution;                // eps_N
  const char* source;
  ScarPreset scar = {0, 0, 0, 0};
};

// Lu et al. 2019's whole-trajectory scar layer at Chant Sura: soil density 1700 kg/m^3 (which
// they take from Dorren 2016), C_f 1.0, and C_s 1.5 and M_e 15 MN/m^2, the values of their
// Table 5 runs (to two figures the means of their per-impact Table 3: C_s 4.0, 1.5, 0.1, 0.5;
// M_e 25, 15, 10, 10 MN/m^2).
constexpr ScarPreset kLu2019Scar = {1700.0, 1.0, 1.5, 15.0};

// The slip law's published sets. Neither Lu et al. nor Bartelt et al. (as Lu quotes them)
// print eps_N for Chant Sura: 0 is Leine et al. 2014's value for their demonstrations (eps_N
// "typically very small"), chosen here. Lu et al. 2019 print no units for kappa and beta; those
// of Leine et al. 2014 (1/m, 1/s) are assumed.
constexpr SlipPreset kSlipPresets[] = {
    {"ramms_chant_sura", 0.55, 2.0, 3.0, 185.0, 0.0,
     "Lu, Caviezel, Christen, Buehler & Bartelt 2019, Landslides 16:2353-2367, rebound plane "
     "at Chant Sura, citing Bartelt, Gerber, Christen & Buehler 2016 (Interpraevent); eps_N 0 "
     "is voxfall's choice (not published for this set)"},
    {"leine2014_demo", 0.2, 1.3, 0.7, 20.0, 0.0,
     "Leine, Schweizer, Christen, Glover, Bartelt & Gerber 2014, Multibody Syst Dyn "
     "32:241-271, section 5.1 (square block on a 45-degree plane); eps_N = eps_T = 0 as there"},
    {"ramms_chant_sura_scar", 0.55, 2.0, 3.0, 185.0, 0.0,
     "Lu, Caviezel, Christen, Buehler & Bartelt 2019, Landslides 16:2353-2367: the rebound plane "
     "of ramms_chant_sura under their soft-soil scar layer (rho 1700 kg/m^3, C_f 1.0, C_s 1.5, "
     "M_e 15 MN/m^2: the whole-trajectory set of their Table 5); eps_N 0 is voxfall's choice",
     kLu2019Scar},
};

}  // namespace

double slipFriction(const GroundCoefficients& c, double s) {
  return c.muMin + 2.0 / std::numbers::pi * (c.muMax - c.muMin) * std::atan(c.kappa * s);
}

std::optional<GroundMaterial> groundPreset(const std::string& name, double friction) {
  for (const Preset& p : kPresets)
    if (name == p.name) {
      GroundMaterial m;
      m.name = name;
      m.restitution = p.restitution;
      m.friction = friction;
      m.rollingResistance = p.rolling;
      m.tangentialRestitution = p.tangential;
      m.source = std::string(kStone) + ", class \"" + p.stoneClass + "\"";
      return m;
    }
  for (const SlipPreset& p : kSlipPresets)
    if (name == p.name) {
      GroundMaterial m;
      m.name = name;
      m.law = GroundLawKind::kSlip;
      m.restitution = p.restitution;
      m.muMin = p.muMin;
      m.muMax = p.muMax;
      m.kappa = p.kappa;
      m.beta = p.beta;
      m.scar = p.scar.density > 0;
      m.scarDensity = p.scar.density;
      m.scarFluidDrag = p.scar.fluidDrag;
      m.scarCompactionDrag = p.scar.compaction;
      m.scarModulus = p.scar.modulus;
      m.source = p.source;
      return m;
    }
  return std::nullopt;
}

std::vector<std::string> groundPresetNames() {
  std::vector<std::string> names;
  for (const Preset& p : kPresets) names.push_back(p.name);
  for (const SlipPreset& p : kSlipPresets) names.push_back(p.name);
  return names;
}

std::int64_t nearestSample(const Heightfield& grid, double x, double y) {
  const long i = std::lround((x - grid.x0) / grid.cell), j = std::lround((y - grid.y0) / grid.cell);
  if (i < 0 || j < 0 || i >= grid.nx || j >= grid.ny) return -1;
  return static_cast<std::int64_t>(j) * grid.nx + i;
}

const GroundMaterial& GroundMap::at(double x, double y) const {
  if (!classes) return materials[0];
  const Heightfield& c = *classes;
  const std::int64_t k = nearestSample(c, x, y);
  if (k < 0) return materials[0];
  const double v = c.z[static_cast<std::size_t>(k)];
  if (std::isnan(v) || v < 0 || v >= static_cast<double>(materialOfClass.size()))
    return materials[0];
  const int m = materialOfClass[static_cast<std::size_t>(v)];
  return m < 0 ? materials[0] : materials[static_cast<std::size_t>(m)];
}

GroundCoefficients GroundMap::coefficientsAt(double x, double y) const {
  const GroundCoefficients& m = at(x, y);
  if (!(variability > 0) || !cells) return m;
  const std::int64_t cell = nearestSample(*cells, x, y);
  if (cell < 0) return m;
  return perturbedCoefficients(m, variability, variabilitySeed, cell);
}

bool GroundMap::hasSlip() const {
  for (const GroundMaterial& m : materials)
    if (m.law == GroundLawKind::kSlip) return true;
  return false;
}

bool GroundMap::hasScar() const {
  for (const GroundMaterial& m : materials)
    if (m.law == GroundLawKind::kSlip && m.scar) return true;
  return false;
}

}  // namespace vf
