// Mesh files to TriMesh. The only file in voxfall that includes assimp.
#pragma once

#include <string>

#include "sim/geometry/tri_mesh.h"

namespace vf {

// Loads every triangle of every mesh in the file (OBJ, STL, PLY, glTF/GLB, and whatever else
// assimp reads), in file units, with node transforms applied. Vertices at the same position are
// welded, so the result is an indexed mesh whose topology can be checked. Throws InputError
// naming the file if it cannot be read or holds no triangles.
TriMesh importMesh(const std::string& path);

}  // namespace vf
