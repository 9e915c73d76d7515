// The two engines' runs behind bullet_compare (bullet_runs.h): voxfall's, and Bullet's of the
// same scene with voxfall's spawn list and the same checker.
#include "tests/bench/bullet_runs.h"

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <LinearMath/btConvexHullComputer.h>
#include <btBulletDynamicsCommon.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/collide/penetration.h"
#include "sim/geometry/mass_properties.h"

namespace {

using vf::bench::kFrame;
using vf::bench::Spawn;

std::string scenePath(const std::string& name) {
  return std::string(VOXFALL_SOURCE_DIR) + "/scenes/" + name + ".toml";
}
// The shared checker: true-mesh interpenetration of the given poses.
double penetration(const vf::World& world, const std::vector<char>& active,
                   const std::vector<vf::BodyState>& states) {
  std::vector<vf::BodyInfo> bodies(world.bodyCount());
  for (int i = 0; i < world.bodyCount(); ++i) {
    bodies[i].shape = world.shapePtr(i);
    bodies[i].isStatic = world.isStatic(i);
    bodies[i].active = active[i] != 0;
    bodies[i].invMass = world.isStatic(i) ? 0 : 1 / world.shape(i).mass;
    bodies[i].inertiaBodyInv = world.shape(i).inertiaBodyInv;
  }
  const vf::Diagnostics d = vf::measureDiagnostics(
      bodies, states, world.def().gravity, world.def().groundHeight, world.def().terrain.get());
  return std::max(d.maxPenetrationBodyBody, d.maxPenetrationBodyGround);
}
btVector3 bt(const vf::Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }

bool isConvex(const vf::TriMesh& m) {
  const double tol = 1e-9 * m.bounds().sizes().maxCoeff();
  for (const auto& t : m.triangles) {
    const vf::Vec3 n =
        (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    for (const vf::Vec3& v : m.vertices)
      if (n.normalized().dot(v - m.vertices[t[0]]) > tol) return false;
  }
  return true;
}

// Volume of the convex hull of the points: Bullet's hull (btConvexHullComputer: its faces'
// edges run counter-clockwise seen from outside), each face fanned into triangles, and
// voxfall's mass properties of that closed mesh. Bullet's hull vertices come out rounded to its
// internal fixed-point grid (0.27 m came back as 0.269988), so each is replaced by the input
// point nearest to it: the volume is then exact to double rounding.
double hullVolume(const std::vector<vf::Vec3>& points) {
  btConvexHullComputer hull;
  hull.compute(points.data()->data(), sizeof(vf::Vec3), static_cast<int>(points.size()), 0, 0);
  vf::TriMesh m;
  for (int i = 0; i < hull.vertices.size(); ++i) {
    const vf::Vec3 v(hull.vertices[i].x(), hull.vertices[i].y(), hull.vertices[i].z());
    m.vertices.push_back(
        *std::min_element(points.begin(), points.end(), [&](const vf::Vec3& a, const vf::Vec3& b) {
          return (a - v).squaredNorm() < (b - v).squaredNorm();
        }));
  }
  for (int f = 0; f < hull.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &hull.edges[hull.faces[f]];
    const int apex = first->getSourceVertex();
    for (const btConvexHullComputer::Edge* e = first->getNextEdgeOfFace();
         e->getTargetVertex() != apex; e = e->getNextEdgeOfFace())
      m.triangles.push_back({static_cast<unsigned>(apex),
                             static_cast<unsigned>(e->getSourceVertex()),
                             static_cast<unsigned>(e->getTargetVertex())});
  }
  return vf::computeMassProperties(m, 1.0).volume;
}

// The cross of example 5 (scenes/meshes/cross.obj: a plus sign in x, y extruded along z, its
// arm ends pointed) as three convex pieces: the bar along x (|y| <= h, h half the arm width,
// the smallest non-zero |y| of a vertex) and the two half arms along y (|x| <= h, y >= h and
// y <= -h). Each piece is the convex hull of the mesh vertices in its region. Checked, since a
// wrong cut would hand Bullet another body: the pieces' hull volumes add up to the mesh's, to
// double rounding (the half arms cut without |x| <= h are 15 % too large). Throws otherwise.
std::vector<std::vector<vf::Vec3>> crossPieces(const vf::Shape& s) {
  const double tol = 1e-9 * s.mesh.bounds().sizes().maxCoeff();
  double h = INFINITY;
  for (const vf::Vec3& v : s.mesh.vertices)
    if (std::abs(v.y()) > tol) h = std::min(h, std::abs(v.y()));
  std::vector<std::vector<vf::Vec3>> pieces(3);
  for (const vf::Vec3& v : s.mesh.vertices) {
    if (std::abs(v.y()) <= h + tol) pieces[0].push_back(v);
    if (std::abs(v.x()) <= h + tol && v.y() >= h - tol) pieces[1].push_back(v);
    if (std::abs(v.x()) <= h + tol && v.y() <= -h + tol) pieces[2].push_back(v);
  }
  double volume = 0;
  for (const auto& piece : pieces) volume += hullVolume(piece);
  if (std::abs(volume - s.volume) > 1e-9 * s.volume)
    throw std::runtime_error("the cross's compound: its pieces' volume " + std::to_string(volume) +
                             " m^3 is not the mesh's " + std::to_string(s.volume));
  return pieces;
}

// Each body's drop height (BodyDef::dropHeight; -1 for none) by body id, in the order
// buildScene adds them: the [[bodies]], then each emitter's releases. Throws if the count is
// not the world's, a sign that the order has changed.
std::vector<double> dropHeights(const vf::SceneSpec& spec, int bodyCount) {
  std::vector<double> out;
  for (const vf::BodySpec& b : spec.bodies) out.push_back(b.dropHeight.value_or(-1));
  for (const vf::EmitterSpec& e : spec.emitters)
    out.insert(out.end(), e.count, e.dropHeight.value_or(-1));
  if (static_cast<int>(out.size()) != bodyCount)
    throw std::runtime_error("drop heights: " + std::to_string(out.size()) +
                             " bodies in the scene's lists, " + std::to_string(bodyCount) +
                             " in its world");
  return out;
}

// Bullet run of the same scene with voxfall's spawn list.
class BulletScene {
 public:
  // `compound`: a non-convex shape as the compound of its convex pieces (crossPieces) instead
  // of GImpact.
  BulletScene(const vf::World& w, const vf::SceneSpec& spec, bool compound)
      : w_(w), compound_(compound) {
    dispatcher_ = std::make_unique<btCollisionDispatcher>(&config_);
    btGImpactCollisionAlgorithm::registerAlgorithm(dispatcher_.get());
    world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), &broadphase_, &solver_,
                                                       &config_);
    world_->setGravity(bt(spec.gravity));
    // Bullet combines restitution and friction as products of the two bodies' values.
    bodyRestitution_ = std::sqrt(spec.contact.restitutionBodyBody);
    groundRestitution_ = spec.contact.restitutionBodyGround / bodyRestitution_;
    bodyFriction_ = std::sqrt(spec.contact.frictionBodyBody);
    groundFriction_ = spec.contact.frictionBodyGround / bodyFriction_;
    if (w.def().groundHeight)
      addStatic(new btStaticPlaneShape(btVector3(0, 0, 1), *w.def().groundHeight),
                btTransform::getIdentity());
    if (const vf::Heightfield* f = w.def().terrain.get()) {
      heights_.assign(f->z.begin(), f->z.end());
      for (double& h : heights_)
        if (std::isnan(h)) h = f->zMin;
      auto* shape =
          new btHeightfieldTerrainShape(f->nx, f->ny, heights_.data(), f->zMin, f->zMax, 2, false);
      shape->setLocalScaling(btVector3(f->cell, f->cell, 1));
      btTransform t = btTransform::getIdentity();
      // Bullet centres the grid on the origin and the height range: move it to voxfall's place.
      t.setOrigin(btVector3(f->x0 + 0.5 * f->cell * (f->nx - 1),
                            f->y0 + 0.5 * f->cell * (f->ny - 1), 0.5 * (f->zMin + f->zMax)));
      addStatic(shape, t);
    }
    bodies_.assign(w.bodyCount(), nullptr);
    dropHeights_ = dropHeights(spec, w.bodyCount());
  }
  ~BulletScene() {
    for (int i = world_->getNumCollisionObjects() - 1; i >= 0; --i) {
      btCollisionObject* o = world_->getCollisionObjectArray()[i];
      world_->removeCollisionObject(o);
      delete btRigidBody::upcast(o)->getMotionState();
      delete o;
    }
    for (btCollisionShape* s : shapes_) delete s;
    for (auto* m : meshes_) delete m;
  }

  void spawn(const Spawn& s) {
    const vf::Shape& shape = w_.shape(s.id);
    btCollisionShape* cs = shapeFor(shape);
    btTransform t(btQuaternion(s.state.q.x(), s.state.q.y(), s.state.q.z(), s.state.q.w()),
                  bt(s.state.x));
    if (dropHeights_[s.id] >= 0 && cs->isConvex())
      dropOntoPile(static_cast<const btConvexShape*>(cs), dropHeights_[s.id], t);
    if (w_.isStatic(s.id)) {
      bodies_[s.id] = addStatic(cs, t);
      return;
    }
    const vf::Vec3 I = shape.inertiaBody.diagonal();  // principal for the scenes' symmetric shapes
    btRigidBody::btRigidBodyConstructionInfo info(shape.mass, new btDefaultMotionState(t), cs,
                                                  bt(I));
    info.m_restitution = bodyRestitution_;
    info.m_friction = bodyFriction_;
    auto* body = new btRigidBody(info);
    body->setLinearVelocity(bt(s.state.P / shape.mass));
    body->setAngularVelocity(bt(w_.angularVelocity(s.id)));
    world_->addRigidBody(body);
    bodies_[s.id] = body;
  }

  // One Bullet step of dt (every call takes exactly one: Bullet's fixed step equals the time
  // it is given).
  void step(double dt) { world_->stepSimulation(dt, 1, dt); }

  std::vector<vf::BodyState> states() const {
    std::vector<vf::BodyState> out(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      if (!bodies_[i]) continue;
      const btTransform& t = bodies_[i]->getWorldTransform();
      const btVector3 o = t.getOrigin();
      const btQuaternion q = t.getRotation();
      out[i].x = vf::Vec3(o.x(), o.y(), o.z());
      out[i].q = vf::Quat(q.w(), q.x(), q.y(), q.z());
    }
    return out;
  }
  // Dynamic bodies that Bullet's next step moves (not deactivated).
  int awake() const {
    int n = 0;
    for (const btRigidBody* b : bodies_) n += b && !b->isStaticObject() && b->isActive() ? 1 : 0;
    return n;
  }
  std::vector<char> active() const {
    std::vector<char> a(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) a[i] = bodies_[i] != nullptr;
    return a;
  }

 private:
  btRigidBody* addStatic(btCollisionShape* shape, const btTransform& t) {
    if (std::find(shapes_.begin(), shapes_.end(), shape) == shapes_.end()) shapes_.push_back(shape);
    btRigidBody::btRigidBodyConstructionInfo info(0, new btDefaultMotionState(t), shape);
    info.m_restitution = groundRestitution_;
    info.m_friction = groundFriction_;
    auto* body = new btRigidBody(info);
    world_->addRigidBody(body);
    return body;
  }

  // A body released at a drop height (BodyDef::dropHeight) falls that far onto what lies below
  // it in voxfall's world, whose pile is not Bullet's: placed at voxfall's height it could start
  // inside Bullet's pile, an overlap the checker would charge to Bullet. So it is placed as
  // voxfall's release rule places it, on Bullet's world: swept straight down from far above
  // until it touches, then raised by the drop height.
  void dropOntoPile(const btConvexShape* shape, double dropHeight, btTransform& t) const {
    constexpr double kFar = 100;  // m above and below: beyond every scene's extent
    btTransform from = t, to = t;
    from.getOrigin().setZ(t.getOrigin().z() + kFar);
    to.getOrigin().setZ(t.getOrigin().z() - kFar);
    btCollisionWorld::ClosestConvexResultCallback hit(from.getOrigin(), to.getOrigin());
    world_->convexSweepTest(shape, from, to, hit);
    if (!hit.hasHit()) return;
    const double touch = from.getOrigin().z() - 2 * kFar * hit.m_closestHitFraction;
    t.getOrigin().setZ(touch + dropHeight);
  }

  btCollisionShape* shapeFor(const vf::Shape& s) {
    auto it = byShape_.find(&s);
    if (it != byShape_.end()) return it->second;
    auto hullOf = [&](const std::vector<vf::Vec3>& points) {
      auto* hull = new btConvexHullShape();
      for (const vf::Vec3& v : points) hull->addPoint(bt(v), false);
      hull->recalcLocalAabb();
      hull->setMargin(0.0);  // the true surface, as voxfall's checker measures it
      return hull;
    };
    btCollisionShape* cs;
    if (isConvex(s.mesh)) {
      cs = hullOf(s.mesh.vertices);
    } else if (compound_) {
      auto* parts = new btCompoundShape();
      for (const std::vector<vf::Vec3>& piece : crossPieces(s)) {
        btConvexHullShape* hull = hullOf(piece);
        shapes_.push_back(hull);
        parts->addChildShape(btTransform::getIdentity(), hull);
      }
      cs = parts;
    } else {
      auto* mesh = new btTriangleMesh();
      for (const auto& t : s.mesh.triangles)
        mesh->addTriangle(bt(s.mesh.vertices[t[0]]), bt(s.mesh.vertices[t[1]]),
                          bt(s.mesh.vertices[t[2]]));
      meshes_.push_back(mesh);
      auto* gimpact = new btGImpactMeshShape(mesh);
      gimpact->updateBound();
      cs = gimpact;
    }
    shapes_.push_back(cs);
    byShape_[&s] = cs;
    return cs;
  }

  const vf::World& w_;
  const bool compound_;
  btDefaultCollisionConfiguration config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<btCollisionShape*> shapes_;
  std::vector<btTriangleMesh*> meshes_;
  std::map<const vf::Shape*, btCollisionShape*> byShape_;
  std::vector<btRigidBody*> bodies_;
  std::vector<double> heights_;
  std::vector<double> dropHeights_;  // per body id, m; < 0: none
  double bodyRestitution_ = 0, groundRestitution_ = 0, bodyFriction_ = 0, groundFriction_ = 0;
};
}  // namespace

namespace vf::bench {

double threadSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

vf::SceneSpec sceneAt(const std::string& name, int level, bool extensions, bool clearance) {
  vf::SceneSpec spec = vf::loadScene(scenePath(name));
  spec.level = level;
  for (vf::ShapeSpec& s : spec.shapes) s.level.reset();
  spec.contactReduction = spec.sleep = extensions;
  spec.step = clearance ? vf::StepRule::clearance() : vf::StepRule::eq20();
  return spec;
}

// One run of `spec`, the clock running only inside World::advanceTo: the spawns recorded and
// (if `check`) the checker applied at every kFrame instant between the timed calls.
Outcome runChecked(const vf::SceneSpec& spec, bool check, std::vector<std::vector<Spawn>>* spawns) {
  Outcome out;
  const int frames = static_cast<int>(std::floor(spec.duration / kFrame + 1e-9));
  vf::BuiltScene built = vf::buildScene(spec);
  vf::World& w = *built.world;
  std::vector<char> active(w.bodyCount(), 0);
  if (spawns) spawns->assign(frames + 1, {});
  double cpu = 0;
  for (int k = 0; k <= frames; ++k) {
    if (k > 0) {
      const double t0 = threadSeconds();
      w.advanceTo(k * kFrame);
      cpu += threadSeconds() - t0;
    }
    std::vector<vf::BodyState> states(w.bodyCount());
    for (int i = 0; i < w.bodyCount(); ++i) {
      states[i] = w.state(i);
      if (w.isActive(i) && !active[i] && spawns) (*spawns)[k].push_back({i, w.state(i)});
      active[i] = w.isActive(i);
    }
    if (check) out.maxPenetration = std::max(out.maxPenetration, penetration(w, active, states));
  }
  out.cpuPerSimSecond = cpu / spec.duration;
  out.stepsPerSimSecond = static_cast<double>(w.totals().steps) / spec.duration;
  out.awakePerSimSecond = static_cast<double>(w.totals().awakeBodySteps) / spec.duration;
  return out;
}

Outcome runVoxfall(const vf::SceneSpec& spec, bool check, std::vector<std::vector<Spawn>>* spawns) {
  Outcome out;
  const int frames = static_cast<int>(std::floor(spec.duration / kFrame + 1e-9));
  {
    vf::BuiltScene built = vf::buildScene(spec);
    const double t0 = threadSeconds();
    for (int k = 1; k <= frames; ++k) built.world->advanceTo(k * kFrame);
    out.cpuPerSimSecond = (threadSeconds() - t0) / spec.duration;
    out.stepsPerSimSecond = static_cast<double>(built.world->totals().steps) / spec.duration;
    out.awakePerSimSecond =
        static_cast<double>(built.world->totals().awakeBodySteps) / spec.duration;
  }
  if (check || spawns) out.maxPenetration = runChecked(spec, check, spawns).maxPenetration;
  return out;
}

Outcome runBullet(const vf::SceneSpec& spec, const std::vector<std::vector<Spawn>>& spawns,
                  bool check, bool compound, int substeps) {
  vf::BuiltScene built = vf::buildScene(spec);  // shapes, ground, and the checker's world
  BulletScene scene(*built.world, spec, compound);
  Outcome out;
  double cpu = 0;
  std::uint64_t awake = 0;
  for (std::size_t k = 0; k < spawns.size(); ++k) {
    for (int s = 0; k > 0 && s < substeps; ++s) {
      awake += static_cast<std::uint64_t>(scene.awake());  // untimed
      const double t0 = threadSeconds();
      scene.step(kFrame / substeps);
      cpu += threadSeconds() - t0;
    }
    for (const Spawn& s : spawns[k]) scene.spawn(s);
    if (check)
      out.maxPenetration =
          std::max(out.maxPenetration, penetration(*built.world, scene.active(), scene.states()));
  }
  out.cpuPerSimSecond = cpu / spec.duration;
  // `substeps` steps per 1/60 s frame, for every frame after the first instant.
  out.stepsPerSimSecond = static_cast<double>((spawns.size() - 1) * substeps) / spec.duration;
  out.awakePerSimSecond = static_cast<double>(awake) / spec.duration;
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string bulletVersion() {
  const int v = btGetVersion();
  return std::to_string(v / 100) + "." + std::to_string(v % 100);
}

}  // namespace vf::bench
