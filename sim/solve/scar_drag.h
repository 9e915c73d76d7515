// The soft-soil scar layer of Lu et al. 2019 over the slip law's ground (rock fall extension;
// opt-in per slip material, `scar`): a velocity-squared drag on a rock while it ploughs the
// layer (scar_drag.cpp).
#pragma once

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

// Per-body scar depth d (m), kept across steps; 0 out of the layer.
class ScarDrag {
 public:
  // The scar depth of body i (m): 0 unless it is in contact with scar ground.
  double depth(std::size_t i) const { return i < depth_.size() ? depth_[i] : 0.0; }

  // After the step's contact solve, per moving body with ground contacts on scar materials
  // carrying normal impulse (N s, in contact order): d becomes the larger of itself and eq. 11
  // for the body's incoming speed along the contacts' normal (its velocity before the solve, as
  // `law` saw it), and the drag F = -1/2 (C_f + C_s) rho A |v| v acts on its centre of mass
  // over dt (v after the solve, A the frontal area at depth d). A body without such a contact
  // has left the layer: d = 0. The materials are those of the contact with the largest normal
  // impulse.
  void afterSolve(const std::vector<Contact>& contacts, const std::vector<double>& normalImpulses,
                  const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                  const GroundMap& ground, const GroundLaw& law, double dt);

 private:
  void dragBody(std::size_t i, const BodyInfo& b, BodyState& y, const Vec3& incoming, double dt);

  std::vector<double> depth_;  // d, m
  // Per-step scratch, per body: the largest normal impulse of a scar contact (N s; 0: none),
  // that contact's material, and the impulse-weighted normal.
  std::vector<double> largest_;
  std::vector<GroundCoefficients> material_;
  std::vector<Vec3> normal_;
};

}  // namespace vf
