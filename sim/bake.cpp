// A bake in memory: its header taken from a built scene, its records from the world after each
// step, and the states it shows between them. The file's writer is bake_write.cpp, its reader
// bake_read.cpp, the header's checks bake_check.cpp.
#include "sim/bake.h"

#include <algorithm>
#include <iterator>
#include <map>

#include "sim/core/error.h"

namespace vf {

std::vector<std::shared_ptr<const Shape>> bakeShapes(const Bake& bake) {
  std::map<std::string, TriMesh> meshes;  // by shapeMeshKey
  std::vector<std::shared_ptr<const Shape>> shapes;
  for (const ShapeSpec& s : bake.scene.shapes) {
    const std::string key = shapeMeshKey(s);
    auto mesh = meshes.find(key);
    if (mesh == meshes.end()) mesh = meshes.emplace(key, shapeSourceMesh(s)).first;
    auto shape = std::make_shared<Shape>();
    shape->name = s.name;
    // centredMesh() is bit-identical to the mesh makeShape() keeps (shape.h).
    shape->mesh = centredMesh(mesh->second, shapeScale(s));
    double farthest = 0;
    for (const Vec3& v : shape->mesh.vertices) farthest = std::max(farthest, v.norm());
    shape->diameter = 2 * farthest;
    shapes.push_back(std::move(shape));
  }
  return shapes;
}

Bake bakeHeader(const SceneSpec& spec, const BuiltScene& built) {
  Bake bake;
  bake.scene = spec;
  bake.scene.bodies.clear();
  bake.scene.emitters.clear();
  const World& world = *built.world;
  for (int id = 0; id < world.bodyCount(); ++id) {
    BakeBody b;
    const auto shape = std::find_if(
        spec.shapes.begin(), spec.shapes.end(),
        [&](const ShapeSpec& s) { return s.name == built.shapeOf[static_cast<std::size_t>(id)]; });
    VF_ASSERT(shape != spec.shapes.end());
    b.shape = static_cast<int>(shape - spec.shapes.begin());
    b.color = built.colors[static_cast<std::size_t>(id)];
    b.isStatic = world.isStatic(id);
    if (!b.isStatic) {
      b.invMass = 1.0 / world.shape(id).mass;
      b.inertiaBodyInv = world.shape(id).inertiaBodyInv;
    }
    bake.bodies.push_back(b);
  }
  return bake;
}

void addBakeRecord(Bake& bake, const World& world) {
  BakeRecord r;
  r.time = world.time();
  r.states.reserve(static_cast<std::size_t>(world.bodyCount()));
  for (int id = 0; id < world.bodyCount(); ++id) {
    r.states.push_back(world.state(id));
    r.active.push_back(world.isActive(id) ? 1 : 0);
  }
  bake.records.push_back(std::move(r));
}

std::vector<BodyState> Bake::statesAt(double t, std::vector<char>& active) const {
  VF_ASSERT(!records.empty());
  // The last record at or before t, with World::advanceTo's tolerance.
  auto after = std::upper_bound(records.begin(), records.end(), t + kTimeTolerance,
                                [](double v, const BakeRecord& r) { return v < r.time; });
  const BakeRecord& r = after == records.begin() ? records.front() : *std::prev(after);
  return sampleSteps(r, after == records.end() || after == records.begin() ? nullptr : &*after, t,
                     active);
}

}  // namespace vf
