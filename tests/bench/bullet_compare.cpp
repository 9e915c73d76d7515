// voxfall against Bullet on the paper's scenes, side by side in one process (built only when
// libbullet-dev is found). Run:
//   cmake --build build --target bullet_compare && build/tests/bench/bullet_compare [rounds]
//
// For each scene: voxfall at level 4 with the eq.-20 step, once with the paper's method and
// once with contact reduction and sleeping; Bullet (btDiscreteDynamicsWorld, sequential-impulse
// solver, DBVT broad phase, one thread, fixed 1/60 s steps). Bullet gets the same meshes
// (convex hull for convex meshes, GImpact for non-convex ones), masses and inertias, the same
// body-body and body-ground restitution and friction (Bullet multiplies the two bodies'
// coefficients: per-body values are chosen so that the products are the scene's), and the same
// spawn list: every body enters Bullet at the 1/60 s instant at which it is active in voxfall,
// with voxfall's state at that instant (so emitters, jitter and drop heights are voxfall's).
// Time: thread CPU time spent stepping (no diagnostics), per simulated second; median over
// interleaved rounds. Interpenetration: one checker for both, World::measure's true-mesh test
// (collide/penetration.h), applied at every 1/60 s instant of an untimed identical run.
// A second table splits each time into steps per simulated second (eq. 20's, or Bullet's 60)
// and CPU time per step; a third counts awake bodies, since a step's cost grows with the bodies
// it moves and both engines let bodies at rest sleep (voxfall's extensions; Bullet's default
// deactivation): awake body-steps per simulated second (voxfall: World's StepStats::awake;
// Bullet: the dynamic bodies isActive() before each step) and CPU time per awake body-step.
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletDynamicsCommon.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sim/collide/penetration.h"
#include "sim/scene/scene.h"

namespace {

constexpr double kFrame = 1.0 / 60;  // instants at which spawns and the checker happen, s

double threadSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string scenePath(const std::string& name) {
  return std::string(VOXFALL_SOURCE_DIR) + "/scenes/" + name + ".toml";
}

struct Spawn {
  int id;
  vf::BodyState state;
};

struct Outcome {
  double cpuPerSimSecond = 0;
  double stepsPerSimSecond = 0;  // the same in every round (the runs are deterministic)
  double awakePerSimSecond = 0;  // awake body-steps per simulated s (the same in every round)
  double maxPenetration = 0;     // m, body-body and body-ground
};

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

// `clearance`: the clearance step rule (solve/time_step.h, an extension) instead of eq. 20.
vf::SceneSpec sceneAt(const std::string& name, int level, bool extensions, bool clearance = false) {
  vf::SceneSpec spec = vf::loadScene(scenePath(name));
  spec.level = level;
  for (vf::ShapeSpec& s : spec.shapes) s.level.reset();
  spec.contactReduction = spec.sleep = extensions;
  spec.step = clearance ? vf::StepRule::clearance() : vf::StepRule::eq20();
  return spec;
}

// voxfall: timed run, then (if spawns or check) an untimed identical one that records spawns
// and applies the checker every kFrame.
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
  if (!check && spawns == nullptr) return out;
  vf::BuiltScene built = vf::buildScene(spec);
  vf::World& w = *built.world;
  std::vector<char> active(w.bodyCount(), 0);
  if (spawns) spawns->assign(frames + 1, {});
  for (int k = 0; k <= frames; ++k) {
    if (k > 0) w.advanceTo(k * kFrame);
    std::vector<vf::BodyState> states(w.bodyCount());
    for (int i = 0; i < w.bodyCount(); ++i) {
      states[i] = w.state(i);
      if (w.isActive(i) && !active[i] && spawns) (*spawns)[k].push_back({i, w.state(i)});
      active[i] = w.isActive(i);
    }
    if (check) out.maxPenetration = std::max(out.maxPenetration, penetration(w, active, states));
  }
  return out;
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

// Bullet run of the same scene with voxfall's spawn list.
class BulletScene {
 public:
  BulletScene(const vf::World& w, const vf::SceneSpec& spec) : w_(w) {
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

  void step() { world_->stepSimulation(kFrame, 1, kFrame); }

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

  btCollisionShape* shapeFor(const vf::Shape& s) {
    auto it = byShape_.find(&s);
    if (it != byShape_.end()) return it->second;
    btCollisionShape* cs;
    if (isConvex(s.mesh)) {
      auto* hull = new btConvexHullShape();
      for (const vf::Vec3& v : s.mesh.vertices) hull->addPoint(bt(v), false);
      hull->recalcLocalAabb();
      hull->setMargin(0.0);  // the true surface, as voxfall's checker measures it
      cs = hull;
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
  double bodyRestitution_ = 0, groundRestitution_ = 0, bodyFriction_ = 0, groundFriction_ = 0;
};

Outcome runBullet(const vf::SceneSpec& spec, const std::vector<std::vector<Spawn>>& spawns,
                  bool check) {
  vf::BuiltScene built = vf::buildScene(spec);  // shapes, ground, and the checker's world
  BulletScene scene(*built.world, spec);
  Outcome out;
  double cpu = 0;
  std::uint64_t awake = 0;
  for (std::size_t k = 0; k < spawns.size(); ++k) {
    if (k > 0) {
      awake += static_cast<std::uint64_t>(scene.awake());  // untimed
      const double t0 = threadSeconds();
      scene.step();
      cpu += threadSeconds() - t0;
    }
    for (const Spawn& s : spawns[k]) scene.spawn(s);
    if (check)
      out.maxPenetration =
          std::max(out.maxPenetration, penetration(*built.world, scene.active(), scene.states()));
  }
  out.cpuPerSimSecond = cpu / spec.duration;
  // One substep per 1/60 s frame, for every frame after the first instant.
  out.stepsPerSimSecond = static_cast<double>(spawns.size() - 1) / spec.duration;
  out.awakePerSimSecond = static_cast<double>(awake) / spec.duration;
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A row of the second table: where the time ratio comes from, steps per simulated second
// times CPU time per step.
struct StepRow {
  std::string scene;
  double steps[4];      // per simulated s: paper, ext, ext + clearance, Bullet
  double usPerStep[4];  // median CPU us per step, the same order
  double awake[4];      // awake body-steps per simulated s, the same order
};

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const char* scenes[] = {"cubes", "blocks", "stack", "crosses", "cliff"};
  std::printf(
      "| scene | voxfall Lv4 paper (ms/sim s) | voxfall Lv4 +reduction+sleep | ext + clearance "
      "step | Bullet 1/60 s | paper / Bullet | ext / Bullet | ext + clearance / Bullet | deepest: "
      "Bullet, voxfall paper, ext, ext + clearance (mm) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  std::vector<StepRow> stepRows;
  for (const char* name : scenes) {
    const vf::SceneSpec paper = sceneAt(name, 4, false);
    const vf::SceneSpec ext = sceneAt(name, 4, true);
    const vf::SceneSpec clear = sceneAt(name, 4, true, true);
    std::vector<std::vector<Spawn>> spawns;
    const Outcome pv = runVoxfall(paper, true, &spawns);
    const Outcome ev = runVoxfall(ext, true, nullptr);
    const Outcome cv = runVoxfall(clear, true, nullptr);
    const Outcome bb = runBullet(paper, spawns, true);
    std::vector<double> tp{pv.cpuPerSimSecond}, te{ev.cpuPerSimSecond}, tc{cv.cpuPerSimSecond},
        tb{bb.cpuPerSimSecond};
    for (int r = 1; r < rounds; ++r) {  // interleaved rounds
      tp.push_back(runVoxfall(paper, false, nullptr).cpuPerSimSecond);
      te.push_back(runVoxfall(ext, false, nullptr).cpuPerSimSecond);
      tc.push_back(runVoxfall(clear, false, nullptr).cpuPerSimSecond);
      tb.push_back(runBullet(paper, spawns, false).cpuPerSimSecond);
    }
    const double p = median(tp), e = median(te), c = median(tc), b = median(tb);
    std::printf(
        "| %s | %.1f | %.1f | %.1f | %.1f | %.2fx | %.2fx | %.2fx | %.0f, %.1f, %.1f, %.1f |\n",
        name, 1e3 * p, 1e3 * e, 1e3 * c, 1e3 * b, p / b, e / b, c / b, 1e3 * bb.maxPenetration,
        1e3 * pv.maxPenetration, 1e3 * ev.maxPenetration, 1e3 * cv.maxPenetration);
    std::fflush(stdout);
    StepRow row{
        name,
        {pv.stepsPerSimSecond, ev.stepsPerSimSecond, cv.stepsPerSimSecond, bb.stepsPerSimSecond},
        {},
        {pv.awakePerSimSecond, ev.awakePerSimSecond, cv.awakePerSimSecond, bb.awakePerSimSecond}};
    const double times[4] = {p, e, c, b};
    for (int i = 0; i < 4; ++i) row.usPerStep[i] = 1e6 * times[i] / row.steps[i];
    stepRows.push_back(row);
  }
  std::printf(
      "\n| scene | steps per simulated s: paper, ext, ext + clearance, Bullet | CPU us per step: "
      "paper, ext, ext + clearance, Bullet | ext / Bullet: steps, per step |\n");
  std::printf("|---|---|---|---|\n");
  for (const StepRow& r : stepRows)
    std::printf("| %s | %.0f, %.0f, %.0f, %.0f | %.1f, %.1f, %.1f, %.1f | %.2fx, %.2fx |\n",
                r.scene.c_str(), r.steps[0], r.steps[1], r.steps[2], r.steps[3], r.usPerStep[0],
                r.usPerStep[1], r.usPerStep[2], r.usPerStep[3], r.steps[1] / r.steps[3],
                r.usPerStep[1] / r.usPerStep[3]);
  std::printf(
      "\n| scene | awake bodies per step: ext, Bullet | awake body-steps per simulated s: ext, "
      "Bullet | CPU us per awake body-step: ext, Bullet | ext / Bullet: awake body-steps, per "
      "awake body-step |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const StepRow& r : stepRows) {
    const double usPerAwake[2] = {r.usPerStep[1] * r.steps[1] / r.awake[1],
                                  r.usPerStep[3] * r.steps[3] / r.awake[3]};
    std::printf("| %s | %.2f, %.2f | %.0f, %.0f | %.2f, %.2f | %.2fx, %.2fx |\n", r.scene.c_str(),
                r.awake[1] / r.steps[1], r.awake[3] / r.steps[3], r.awake[1], r.awake[3],
                usPerAwake[0], usPerAwake[1], r.awake[1] / r.awake[3],
                usPerAwake[0] / usPerAwake[1]);
  }
  return 0;
}
