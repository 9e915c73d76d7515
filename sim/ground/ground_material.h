// Ground materials for rock fall: what a rock loses where it meets the ground, chosen per
// material and, with a class raster, per DEM cell. Opt-in: a scene without `[ground] material`
// keeps the paper's model ([contact] body_ground restitution and friction, nothing else).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/shape/heightfield.h"

namespace vf {

struct GroundMaterial {
  std::string name;
  double restitution = 0.3;  // normal (Newton) coefficient eps of eq. 15
  double friction = 0.8;     // kinetic Coulomb mu
  // Rolling resistance mu_r (tan of the rolling friction angle, Azzoni et al. 1995): a torque
  // opposing rolling of at most mu_r h N (h: centre-of-mass height above the contact, N the
  // normal force). 0: none (the paper's model).
  double rollingResistance = 0;
  // Tangential restitution Rt (STONE): a bounce keeps at most Rt of the incoming tangential
  // velocity of the centre of mass (sim/solve/ground_law.cpp). 1: no loss beyond friction's.
  double tangentialRestitution = 1;
  std::string source;  // where the numbers come from (presets)
};

// A preset by name (the STONE per-lithology table, see ground_material.cpp), with the given
// Coulomb friction (STONE has none: it is a lumped-mass model); nothing if unknown.
std::optional<GroundMaterial> groundPreset(const std::string& name, double friction);
// The preset names, in table order (for error messages and the README).
std::vector<std::string> groundPresetNames();

// Which material lies where: one material everywhere, or a class raster on the DEM's grid
// (one integer class per sample) with a class -> material table.
struct GroundMap {
  std::vector<GroundMaterial> materials;  // [0] is used where no class raster says otherwise
  std::shared_ptr<const Heightfield>
      classes;                       // class per sample (same grid as the DEM); null: one material
  std::vector<int> materialOfClass;  // index by class value (0 .. size-1); -1: not mapped
  // The material at world (x, y): the class of the nearest sample, else materials[0].
  const GroundMaterial& at(double x, double y) const;
};

}  // namespace vf
