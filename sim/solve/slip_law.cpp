// The slippage of the RAMMS-type ground law (Leine, Schweizer, Christen, Glover, Bartelt &
// Gerber 2014, Multibody Syst Dyn 32:241-271; Lu et al. 2019, Landslides 16:2353-2367).
//
// The law: a Newton impact with a small eps_N (eq. 38), no tangential restitution (eq. 40),
// and Coulomb friction whose coefficient grows with the slippage s, the path of the centre of
// mass while in contact with the terrain (eq. 46):
//     mu(s) = mu_min + (2/pi)(mu_max - mu_min) atan(kappa s),
//     ds/dt = |v|          while a terrain contact carries normal force,
//     ds/dt = -beta s      otherwise (eq. 47).
// A rock that slides digs in: its friction rises until it tips or stops; in flight the scar
// heals. Here eps_N is the solver's restitution of the material (eq. 15, unchanged), and mu(s)
// is the solver's Coulomb coefficient of the body's slip-material contacts, read from s as it
// stood at the start of the step (SolverSettings::slippage). After the solve this file advances
// s over the step: by |v| dt with v the velocity after the solve (the one the step moves the
// body by, so s is the path integrate() takes), or by the exact decay factor exp(-beta dt).
//
// Mixed ground (a class raster with STONE and slip classes): s is the body's, one number;
// every slip-material contact reads its own material's mu(s) at that s. Only slip-material
// contacts count as "in contact" for s (a rock on STONE ground is not scarring soil, so its s
// decays there), and the decay uses the beta of the slip contact that carried the largest
// normal impulse in the body's last step on slip ground (one material's value, as it is: a
// weighted mean would mix materials and round). STONE's bounce and rolling act on STONE
// contacts only (ground_law.cpp).
//
// A sleeping body is not stepped, and its s stays as it was: at rest on the ground s would
// grow by |v| dt = 0 anyway.
#include "sim/solve/slip_law.h"

#include <cmath>

namespace vf {

void SlipLaw::resize(std::size_t bodies) {
  if (s_.size() < bodies) {
    s_.resize(bodies, 0.0);
    beta_.resize(bodies, 0.0);
  }
}

void SlipLaw::afterSolve(const std::vector<Contact>& contacts,
                         const std::vector<double>& normalImpulses,
                         const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                         const GroundMap& ground, double dt) {
  const std::size_t nb = bodies.size();
  resize(nb);
  stepBeta_.resize(nb);
  largest_.assign(nb, 0.0);
  for (std::size_t k = 0; k < contacts.size(); ++k) {  // contact order: ties go to the first
    const Contact& c = contacts[k];
    const double jn = normalImpulses[k];
    if (c.b != kGround || !(jn > largest_[c.a])) continue;
    const GroundCoefficients m = ground.coefficientsAt(c.point.x(), c.point.y());
    if (m.law != GroundLawKind::kSlip) continue;
    largest_[c.a] = jn;
    stepBeta_[c.a] = m.beta;
  }
  for (std::size_t i = 0; i < nb; ++i) {
    if (!bodies[i].moves()) continue;
    if (largest_[i] > 0) {  // in contact: s += |v_S| dt (eq. 47)
      s_[i] += velocityOf(bodies[i], states[i]).norm() * dt;
      beta_[i] = stepBeta_[i];
    } else if (s_[i] > 0) {  // out of contact: the exact solution of ds/dt = -beta s
      s_[i] *= std::exp(-beta_[i] * dt);
    }
  }
}

}  // namespace vf
