// Forces and time integration (section 2, eqs. 1-7).
#pragma once

#include <cstdint>
#include <vector>

#include "sim/core/body.h"
#include "sim/solve/rotation_update.h"

namespace vf {

class WorkerPool;

// P += M g dt for every moving body (gravity is the only force; contacts act as impulses).
void applyGravity(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                  const Vec3& gravity, double dt);

// Explicit Euler on {x, q} with the current momenta: x += dt P/M, q += dt (1/2) [0, w] q with
// w = R I_body^-1 R^T L, then q is renormalised. A body whose state is not finite keeps its
// previous pose with zero momenta; the return value counts such bodies. Bodies are split
// over the threads of `pool` if given (each body's update is its own: the same bits).
std::uint64_t integrate(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                        double dt, RotationUpdate rotation = RotationUpdate::kExplicitEuler,
                        WorkerPool* pool = nullptr);

// The motion of a step without contacts, over dt seconds (nothing for dt <= 0): applyGravity
// then integrate. Shows states between steps (World::statesAt, Bake::statesAt).
void freeMotion(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                const Vec3& gravity, double dt);

// dq/dt = 1/2 [0, w] q (eq. 7 with the factor 1/2 the paper's printing drops).
Quat quaternionRate(const Vec3& w, const Quat& q);

}  // namespace vf
