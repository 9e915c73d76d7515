// Collision response: restitution impulses (eq. 15) with Coulomb friction, many contacts
// resolved sequentially.
#pragma once

#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/solve/contact_cache.h"
#include "sim/solve/patch_block.h"

namespace vf {

struct GroundMap;  // sim/ground/ground_material.h
class WorkerPool;  // sim/core/worker_pool.h

// Denominator of eq. 15 for direction d at lever arms ra, rb (inverse effective mass):
// 1/M1 + 1/M2 + d . [ (I1^-1 (r1 x d)) x r1 + (I2^-1 (r2 x d)) x r2 ].
double inverseEffectiveMass(double invMassA, const Mat3& invInertiaA, const Vec3& ra,
                            double invMassB, const Mat3& invInertiaB, const Vec3& rb,
                            const Vec3& d);

struct SolverSettings {
  ContactMaterial material;
  int iterations = 12;
  // Stop before `iterations` passes once a pass changes no accumulated impulse: every later
  // pass would repeat it, so the result is the same. Off only to test that claim.
  bool stopWhenConverged = true;
  // Patch blocks (an extension, used with contact reduction): before the rows of a patch
  // (2-4 consecutive contacts of one body pair with the same normal), their normal impulses
  // are solved together as one small linear system. See impulse.cpp.
  bool patchBlocks = false;
  // Contact reduction's warm start (an extension, with contact reduction): a contact that
  // matches no cached key takes the impulse of the nearest unclaimed cached contact of its body
  // pair within representativeReach (contact_cache.cpp).
  bool warmStartNearest = false;
  // Approach speeds below this get no restitution: the speed gravity adds in a step or two.
  // Without it a resting body would bounce by eps g dt every step (visible jitter).
  double restingSpeed = 0;
  double dt = 0;  // step length, s: scales the warm start
  // Rock fall (opt-in): ground contacts take restitution and friction from the ground
  // material under the contact point instead of `material`; null: the paper's model.
  const GroundMap* ground = nullptr;
  // Per body, the slippage s (m) of the slip law (slip_law.h): a contact on a slip material
  // takes friction mu(s) of its body's s. Null or shorter than the bodies: s = 0.
  const std::vector<double>* slippage = nullptr;
  // Threads solving the contact islands (each island on one thread; the result is the same
  // bits for any count); none: the calling thread alone.
  WorkerPool* pool = nullptr;
  // If set, receives the number of passes made (at most `iterations`).
  int* passes = nullptr;
  // If set, receives each contact's accumulated normal impulse (N s), in contact order.
  std::vector<double>* normalImpulses = nullptr;
};

// Resolves every contact and applies the impulses to P and L of the bodies involved
// (P1 += J, L1 += r1 x J; the opposite on body 2). Contacts with the ground or a static body use
// the body-ground material, others body-body. See impulse.cpp for the scheme.
// `cache` holds the previous step's impulses on entry and this step's on return, together with
// those of sleeping bodies' contacts (keepSleepingContacts).
void solveContacts(const std::vector<Contact>& contacts, const std::vector<BodyInfo>& bodies,
                   std::vector<BodyState>& states, const SolverSettings& settings,
                   ContactCache& cache);

}  // namespace vf
