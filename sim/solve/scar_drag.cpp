// The soft-soil scar layer of Lu, Caviezel, Christen, Buehler & Bartelt 2019 (Landslides
// 16:2353-2367, eqs. 9-12), on the slip law's ground.
//
// Their model: the terrain is a deformable scarring layer Sigma over a hard "rebound plane"
// Lambda. A rock that strikes the ground ploughs Sigma, braked by a drag at its centre of mass
//     F = 1/2 C_d rho_Sigma A |v|^2, against the motion (eq. 9), C_d = C_f + C_s (eq. 12),
// A the frontal area of the rock's part in the soil, projected normal to the motion, down to
//     d_max = 0.1 M^(1/3) M_e^(-0.4) |V_perp|^0.8 (eq. 11, Gerber's fit;
//                                                  M kg, M_e kN/m^2, V_perp m/s),
// where it meets Lambda and slides on it with the slip law's mu(s) (slip_law.cpp) until it
// rebounds.
//
// How it sits in voxfall's step. The step rule keeps bodies out of the ground, so the ground
// surface the contacts see is Lambda, and Sigma is a layer of thickness d over it, where the
// rock struck:
//  - A strike is a step with ground contact on scar ground: d becomes eq. 11 for the speed of
//    the centre of mass towards the ground (along the contacts' impulse-weighted normal) before
//    the step's solve, or stays what it was if that is more (a rock that lands hard and slides
//    or rolls on ploughs on at the depth of its scar, as on Lambda). Lu et al. write V_perp as
//    the vertical impact speed; the speed along the ground's normal is the same on level
//    ground, where Gerber's drop tests measured it, and is the one that presses a rock into a
//    slope.
//  - The rock is in the layer, and ploughs it, until every leaf sphere of its sphere tree is
//    more than d above the ground (clearOfGround, the test of STONE's lift-off): it rebounds
//    out of the scar through the soil, as in Lu et al.'s rebound phase. Then d = 0, and the
//    next strike starts a new scar. A contact on ground without the layer ends it too.
//  - The drag acts in every step in the layer, with v the velocity after the solve (the one the
//    step moves the body by), A at depth d, and the normal and material of the last strike. Over
//    the step it is applied as the exact solution of dv/dt = -k |v| v, k = 1/2 C_d rho A / m: v /
//    (1 + k |v| dt), which slows the body along its motion and never reverses it. The spin is
//    untouched (F acts at the centre of mass, as in eq. 9).
//  - A: the body is replaced by its equivalent ellipsoid, the solid ellipsoid of the same mass
//    and inertia, whose semi-axis matrix S = E E^T is (5 / m)(tr(I) / 2 - I) (the second moment
//    of mass of a solid ellipsoid is m E E^T / 5). For the ellipsoid the area is exact: the
//    linear map E takes the unit sphere to it, the part within d of the lowest point to a cap
//    of height d / sqrt(n^T S n) (n the ground normal), and a direction t normal to n to one
//    normal to the cap's axis; a convex set's shadow area scales under E by |det E| |E^-1 t|,
//    and a unit cap's shadow across its axis is the circle segment of its height. So
//        A = sqrt(det S) sqrt(t^T S^-1 t) seg(d / sqrt(n^T S n)),
//    seg(h) = acos(1 - h) - (1 - h) sqrt(2 h - h^2), t the direction of the motion along the
//    ground. For a sphere of radius R this is R^2 seg(d / R), the circular segment of depth d;
//    a rock rolling about its long axis ploughs with its whole length.
// Approximations, each documented in docs/rockfall.md:
//  - The penetration of Sigma, a path of order d during which the immersed area grows from 0,
//    is not stepped: the rock is at Lambda from the first step of contact, with the full area,
//    and keeps the full area until it clears the layer (its area shrinks on the way out).
//    The drag on the normal motion over that path (at most 1/2 C_d rho A V_perp^2 d of work)
//    is left out; the Newton impact on Lambda (eps_N) takes that motion instead.
//  - An angular rock that strikes corner first immerses less than its ellipsoid, face first
//    more. A per-leaf area from the sphere tree would cost a tree walk per body and step for an
//    error smaller than the spread of C_s between Lu et al.'s impacts (0.1 to 4.0).
//  - Scar coefficients are not perturbed by per-cell variability.
// Alternatives rejected: lowering the contact surface by d (a soft contact) breaks the step
// rule, which keeps every body out of the ground it touches.
#include "sim/solve/scar_drag.h"

#include <algorithm>
#include <cmath>

#include "sim/shape/shape.h"

namespace vf {

double scarDepth(double mass, double modulus, double normalSpeed) {
  const double kiloNewtonsPerSquareMetre = 1000.0 * modulus;  // eq. 11's unit (MN -> kN)
  return 0.1 * std::cbrt(mass) * std::pow(kiloNewtonsPerSquareMetre, -0.4) *
         std::pow(std::abs(normalSpeed), 0.8);
}

double unitSegmentArea(double h) {
  h = std::clamp(h, 0.0, 2.0);
  const double c = 1.0 - h;
  return std::acos(c) - c * std::sqrt(std::max(0.0, 2.0 * h - h * h));
}

double immersedFrontalArea(const BodyInfo& b, const BodyState& y, const Vec3& n, const Vec3& t,
                           double depth) {
  const Mat3& I = b.shape->inertiaBody;
  const double mass = 1.0 / b.invMass;
  const Mat3 S = (5.0 / mass) * (0.5 * I.trace() * Mat3::Identity() - I);  // body frame
  const Mat3 Rt = y.q.toRotationMatrix().transpose();
  const Vec3 nb = Rt * n, tb = Rt * t;
  const double halfHeight = std::sqrt(nb.dot(S * nb));
  const double width = std::sqrt(S.determinant() * tb.dot(S.inverse() * tb));
  return width * unitSegmentArea(depth / halfHeight);
}

void ScarDrag::afterSolve(const std::vector<Contact>& contacts,
                          const std::vector<double>& normalImpulses,
                          const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                          const GroundMap& ground, const GroundLaw& law, double dt,
                          const Heightfield* terrain, std::optional<double> floor) {
  const std::size_t nb = bodies.size();
  if (layers_.size() < nb) layers_.resize(nb);
  largest_.assign(nb, 0.0);
  material_.resize(nb);
  normal_.assign(nb, Vec3::Zero());
  otherGround_.assign(nb, 0);
  for (std::size_t k = 0; k < contacts.size(); ++k) {  // contact order: ties go to the first
    const Contact& c = contacts[k];
    const double jn = normalImpulses[k];
    if (c.b != kGround || !(jn > 0)) continue;
    const GroundCoefficients m = ground.coefficientsAt(c.point.x(), c.point.y());
    if (m.law != GroundLawKind::kSlip || !m.scar) {
      otherGround_[c.a] = 1;
      continue;
    }
    normal_[c.a] += jn * c.normal;
    if (!(jn > largest_[c.a])) continue;
    largest_[c.a] = jn;
    material_[c.a] = m;
  }
  for (std::size_t i = 0; i < nb; ++i)
    if (bodies[i].moves())
      dragBody(i, bodies[i], states[i], law.incomingVelocity(i), dt, terrain, floor);
}

void ScarDrag::dragBody(std::size_t i, const BodyInfo& b, BodyState& y, const Vec3& incoming,
                        double dt, const Heightfield* terrain, std::optional<double> floor) {
  Layer& layer = layers_[i];
  const double mass = 1.0 / b.invMass;
  if (largest_[i] > 0 && !otherGround_[i]) {  // a strike (or a step of one) on scar ground
    layer.normal = normal_[i].normalized();
    layer.material = material_[i];
    const double towards = std::max(0.0, -incoming.dot(layer.normal));
    layer.depth = std::max(layer.depth, scarDepth(mass, layer.material.scarModulus, towards));
  } else if (otherGround_[i] || (layer.depth > 0 && clearOfGround(b, y, terrain, floor, layer.depth,
                                                                  layer.nearLeaf))) {
    layer.depth = 0;  // on other ground, or risen out of the layer
  }
  if (!(layer.depth > 0)) return;
  const GroundCoefficients& m = layer.material;
  const Vec3 v = velocityOf(b, y);
  const Vec3 along = v - v.dot(layer.normal) * layer.normal;
  if (!(along.norm() > 0)) return;
  const double area = immersedFrontalArea(b, y, layer.normal, along.normalized(), layer.depth);
  const double k = 0.5 * (m.scarFluidDrag + m.scarCompactionDrag) * m.scarDensity * area / mass;
  y.P /= 1.0 + k * v.norm() * dt;  // eq. 9 over the step: the exact solution of dv/dt = -k|v|v
}

}  // namespace vf
