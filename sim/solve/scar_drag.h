// The soft-soil scar layer of Lu et al. 2019 over the slip law's ground (rock fall extension;
// opt-in per slip material, `scar`): a velocity-squared drag on a rock while it ploughs the
// layer (scar_drag.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/ground/ground_material.h"
#include "sim/solve/ground_law.h"

namespace vf {

// Lu et al. 2019 eq. 11 (Gerber's fit): the depth a rock of mass `mass` (kg) ploughs into soil
// of deformation modulus `modulus` (MN/m^2) when it strikes it at `normalSpeed` (m/s, towards
// the ground), in m: 0.1 M^(1/3) M_e^(-0.4) |V_perp|^0.8 with M_e in kN/m^2.
double scarDepth(double mass, double modulus, double normalSpeed);

// The area of the segment of height h (0 <= h <= 2) of the unit circle.
double unitSegmentArea(double h);

// The frontal area (m^2) of the part of a body within `depth` (m) of its lowest point along the
// ground normal `n` (unit, out of the ground), projected along a unit direction `t` normal to
// n: for the body's equivalent ellipsoid (same mass and inertia), exactly (scar_drag.cpp).
double immersedFrontalArea(const BodyInfo& b, const BodyState& y, const Vec3& n, const Vec3& t,
                           double depth);

// Per-body scar layer: its depth d (m), kept across steps; 0 out of the layer.
class ScarDrag {
 public:
  // The scar depth of body i (m): 0 out of the layer.
  double depth(std::size_t i) const { return i < layers_.size() ? layers_[i].depth : 0.0; }

  // After the step's contact solve, per moving body. With ground contacts on scar materials
  // carrying normal impulse (N s, in contact order) it strikes the layer: d becomes the larger of
  // itself and eq. 11 for the body's incoming speed along the contacts' normal (its velocity
  // before the solve, as `law` saw it). Without ground contact it stays in the layer while a
  // leaf sphere is within d of the terrain or the floor plane (clearOfGround), and leaves it
  // (d = 0) once clear; a contact on other ground ends it too. In the layer the drag
  // F = -1/2 (C_f + C_s) rho A |v| v acts on its centre of mass over dt (v after the solve, A
  // the frontal area at depth d), with the material and normal of its last scar contact (that
  // of the largest normal impulse).
  void afterSolve(const std::vector<Contact>& contacts, const std::vector<double>& normalImpulses,
                  const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                  const GroundMap& ground, const GroundLaw& law, double dt,
                  const Heightfield* terrain, std::optional<double> floor);

 private:
  void dragBody(std::size_t i, const BodyInfo& b, BodyState& y, const Vec3& incoming, double dt,
                const Heightfield* terrain, std::optional<double> floor);

  struct Layer {
    double depth = 0;             // d, m; 0: out of the layer
    Vec3 normal = Vec3::UnitZ();  // of the last scar contact, out of the ground
    GroundCoefficients material;  // of the last scar contact
    std::uint32_t nearLeaf = 0;   // clearOfGround's hint
  };
  std::vector<Layer> layers_;
  // Per-step scratch, per body: the largest normal impulse of a scar contact (N s; 0: none),
  // that contact's material, the impulse-weighted normal, and whether other ground was touched.
  std::vector<double> largest_;
  std::vector<GroundCoefficients> material_;
  std::vector<Vec3> normal_;
  std::vector<char> otherGround_;
};

}  // namespace vf
