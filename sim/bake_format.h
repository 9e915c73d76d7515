// The bake file's layout, shared by its writer (bake_write.cpp), its reader (bake_read.cpp)
// and the header's checks (bake_check.cpp); the format itself is in docs/output-formats.md
// ("Bake files").
// Internal to the bake: other code includes sim/bake.h.
#pragma once

#include <string>

#include "sim/bake.h"

namespace vf {

inline constexpr char kBakeSignature[] = "VOXFALL-BAKE 1\n";
// 2: the header holds the scene's named cameras ([cameras.NAME]) as well; 1 is still read.
// 3: each shape holds its up axis, repair flag and generated rock; 1 and 2 are still read.
// 4: the scene's [light], the terrain's texture, each shape's `smooth` and each camera's
// `offset_given`; 1 to 3 are still read.
inline constexpr int kBakeVersion = 4;
inline constexpr int kBakeValuesPerBody = 14;  // active, x(3), q(w, x, y, z), P(3), L(3)

// The values a bake's header may hold: what a scene file may give (scene_loader.cpp) and what a
// run writes. A header edited by hand or damaged gets the first problem, named by its key in
// the header and `where`, as an InputError, instead of a drawing of nonsense or an allocation
// that fails. (Colours and integers are checked as they are read, in bake_read.cpp.)
void checkBakeHeader(const Bake& bake, const std::string& where);

}  // namespace vf
