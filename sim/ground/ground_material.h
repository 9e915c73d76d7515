// Ground materials for rock fall: what a rock loses where it meets the ground, chosen per
// material and, with a class raster, per DEM cell. Opt-in: a scene without `[ground] material`
// keeps the paper's model ([contact] body_ground restitution and friction, nothing else).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/shape/heightfield.h"

namespace vf {

// Which contact law a material's contacts follow (docs/rockfall.md):
//  - kStone: STONE's flight, bounce and rolling on a rigid body (sim/solve/ground_law.cpp);
//  - kSlip: RAMMS-type slippage-dependent Coulomb friction (Leine et al. 2014, Multibody Syst
//    Dyn 32:241-271, eqs. 46-47; sim/solve/slip_law.cpp), with a Newton impact of restitution
//    eps_N and neither tangential restitution nor rolling resistance.
enum class GroundLawKind { kStone, kSlip };

// The numbers of a ground material: what the solver and the ground laws read per contact.
struct GroundCoefficients {
  GroundLawKind law = GroundLawKind::kStone;
  double restitution = 0.3;  // normal (Newton) coefficient eps of eq. 15 (eps_N of the slip law)
  double friction = 0.8;     // kinetic Coulomb mu (stone law; the slip law uses mu(s))
  // Rolling resistance mu_r (tan of the rolling friction angle, Azzoni et al. 1995): a torque
  // opposing rolling of at most mu_r h N (h: centre-of-mass height above the contact, N the
  // normal force). 0: none (the paper's model). Stone law only.
  double rollingResistance = 0;
  // Tangential restitution Rt (STONE): a bounce keeps at most Rt of the incoming tangential
  // velocity of the centre of mass (sim/solve/ground_law.cpp). 1: no loss beyond friction's.
  double tangentialRestitution = 1;
  // Slip law, mu(s) = muMin + (2/pi)(muMax - muMin) atan(kappa s) (Leine et al. 2014 eq. 46),
  // s the body's slippage (m); out of contact s decays as exp(-beta t) (eq. 47).
  double muMin = 0, muMax = 0;
  double kappa = 0;  // 1/m, slippage hardening
  double beta = 0;   // 1/s, slippage softening
  // Slip law only: the soft-soil scar layer of Lu et al. 2019 above the ground, which acts as
  // their hard "rebound plane" (sim/solve/scar_drag.cpp). Off unless `scar` is true.
  bool scar = false;
  double scarDensity = 0;         // rho_Sigma, kg/m^3: the soil's density
  double scarFluidDrag = 0;       // C_f: the fluid part of the drag coefficient
  double scarCompactionDrag = 0;  // C_s: the compaction part of the drag coefficient
  double scarModulus = 0;         // M_e, MN/m^2: the soil's deformation modulus (eq. 11)
};

struct GroundMaterial : GroundCoefficients {
  std::string name;
  std::string source;  // where the numbers come from (presets)
};

// The slip law's Coulomb coefficient at slippage s >= 0 (m): Leine et al. 2014 eq. 46.
double slipFriction(const GroundCoefficients& c, double s);

// A preset by name (the STONE per-lithology table and the slip-law sets, see
// ground_material.cpp); STONE presets take the given Coulomb friction (STONE has none: it is a
// lumped-mass model). Nothing if unknown.
std::optional<GroundMaterial> groundPreset(const std::string& name, double friction);
// The preset names, in table order (for error messages and the README).
std::vector<std::string> groundPresetNames();

// Which material lies where: one material everywhere, or a class raster on the DEM's grid
// (one integer class per sample) with a class -> material table; optionally each material's
// coefficients perturbed per DEM cell (sim/ground/ground_variability.h).
struct GroundMap {
  std::vector<GroundMaterial> materials;  // [0] is used where no class raster says otherwise
  std::shared_ptr<const Heightfield>
      classes;                       // class per sample (same grid as the DEM); null: one material
  std::vector<int> materialOfClass;  // index by class value (0 .. size-1); -1: not mapped
  // Per-cell variability: each coefficient of the law in force is scaled, per DEM sample's
  // cell, by a factor drawn within 1 +- variability (ground_variability.h). 0: off.
  double variability = 0;
  std::uint64_t variabilitySeed = 1;
  std::shared_ptr<const Heightfield> cells;  // the DEM whose samples are the cells (variability)
  // The material at world (x, y): the class of the nearest sample, else materials[0].
  const GroundMaterial& at(double x, double y) const;
  // The coefficients at world (x, y): at(x, y)'s, perturbed for the nearest DEM sample's cell
  // when variability > 0 (unperturbed off the grid).
  GroundCoefficients coefficientsAt(double x, double y) const;
  // Whether any material follows the slip law.
  bool hasSlip() const;
  // Whether any material has a scar layer.
  bool hasScar() const;
};

// The index j * nx + i of the sample nearest to world (x, y), or -1 off the grid.
std::int64_t nearestSample(const Heightfield& grid, double x, double y);

}  // namespace vf
