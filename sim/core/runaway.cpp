// The wording of a stopped run's message.
#include "sim/core/runaway.h"

#include <cstdio>

namespace vf {

std::string guardNumber(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

std::string guardBodyName(int id, const std::string& shape) {
  return "body " + std::to_string(id) + " (shape '" + shape + "')";
}

std::string Runaway::message() const {
  const std::string who = guardBodyName(body, shape) + " at t = " + guardNumber(time) + " s: ";
  if (quantity == "non-finite state")
    return who +
           "its state is no longer finite (NaN or infinity); the simulation has left "
           "physics: check for bodies that start inside each other or under the terrain";
  if (quantity == "speed")
    return who + "speed " + guardNumber(value) + " m/s (|v| + (l/2)|w|) exceeds the limit of " +
           guardNumber(limit) +
           " m/s; the simulation has left physics (a body that started inside another or under "
           "the terrain, or a step too long for the level), or raise the limit with "
           "--max-speed or [simulation] max_speed";
  return who + "total energy rose by " + guardNumber(value) + " J, over the allowed " +
         guardNumber(limit) +
         " J (energy at release plus margin); the simulation has left physics (check for "
         "bodies that start inside each other, or use a finer level or a shorter step)";
}

RunawayError::RunawayError(const Runaway& r) : std::runtime_error(r.message()), runaway_(r) {}

}  // namespace vf
