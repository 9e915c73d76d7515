// voxfall against Bullet on the paper's scenes, side by side in one process (built only when
// libbullet-dev is found). Run:
//   cmake --build build --target bullet_compare && build/tests/bench/bullet_compare [rounds]
//
// For each scene: voxfall at level 4 with the eq.-20 step, once with the paper's method and
// once with contact reduction and sleeping; Bullet (btDiscreteDynamicsWorld, sequential-impulse
// solver, DBVT broad phase, one thread, fixed 1/60 s steps). Bullet gets the same meshes
// (convex hull for convex meshes, GImpact for non-convex ones; for the crosses also, as a second
// row, the compound of the cross's three convex pieces, Bullet's usual answer to a non-convex
// body, "a compound of 3 boxes"), masses and inertias, the same
// body-body and body-ground restitution and friction (Bullet multiplies the two bodies'
// coefficients: per-body values are chosen so that the products are the scene's), and the same
// spawn list: every body enters Bullet at the 1/60 s instant at which it is active in voxfall,
// with voxfall's state at that instant (so emitters, jitter and drop heights are voxfall's).
// Time: thread CPU time spent stepping (no diagnostics), per simulated second; median over
// interleaved rounds. Interpenetration: one checker for both, World::measure's true-mesh test
// (collide/penetration.h), applied at every 1/60 s instant of an untimed identical run.
// The cliff is measured once with the scene's throw and once over 20 throws (the scene's seed
// and the 19 after it: the paper varies the throw's direction from run to run), each run's
// times, steps and awake bodies summed and its deepest interpenetration the largest.
// A second table splits each time into steps per simulated second (eq. 20's, or Bullet's 60)
// and CPU time per step; a third counts awake bodies, since a step's cost grows with the bodies
// it moves and both engines let bodies at rest sleep (voxfall's extensions; Bullet's default
// deactivation): awake body-steps per simulated second (voxfall: World's StepStats::awake;
// Bullet: the dynamic bodies isActive() before each step) and CPU time per awake body-step.
// A fourth table runs Bullet again at about eq. 20's rate (the whole number of steps per 1/60 s
// nearest to voxfall's with the extensions): the two engines at equal step counts, and how deep
// Bullet goes at the step at which voxfall does not interpenetrate.
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <LinearMath/btConvexHullComputer.h>
#include <btBulletDynamicsCommon.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/collide/penetration.h"
#include "sim/geometry/mass_properties.h"
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
  double bodyRestitution_ = 0, groundRestitution_ = 0, bodyFriction_ = 0, groundFriction_ = 0;
};

// `substeps`: Bullet steps per 1/60 s frame (1: Bullet's usual 1/60 s; more: the rate at which
// voxfall's eq. 20 steps, for the comparison at equal step counts).
Outcome runBullet(const vf::SceneSpec& spec, const std::vector<std::vector<Spawn>>& spawns,
                  bool check, bool compound, int substeps = 1) {
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

// A row of the second table: where the time ratio comes from, steps per simulated second
// times CPU time per step.
struct StepRow {
  std::string scene;
  double steps[4];      // per simulated s: paper, ext, ext + clearance, Bullet
  double usPerStep[4];  // median CPU us per step, the same order
  double awake[4];      // awake body-steps per simulated s, the same order
};

// A row of the fourth table: voxfall with the extensions against Bullet stepping about as often
// as eq. 20 does (eq. 20's steps per 1/60 s, rounded to a whole number of Bullet steps).
struct RateRow {
  std::string scene;
  int substeps;       // Bullet steps per 1/60 s
  double steps[2];    // per simulated s: ext, Bullet
  double cpu[2];      // median CPU s per simulated s, the same order
  double deepest[2];  // m, the same order
};

// A row of the tables: a scene, Bullet's shape for non-convex bodies, and how many throws (the
// scene's emitter seed and the ones after it).
struct Case {
  const char* label;
  const char* scene;
  bool compound;
  int throws;
};

// Several runs as one: times, steps and awake body-steps summed over the runs and divided by
// their simulated time in all; the deepest interpenetration the largest.
Outcome together(const std::vector<Outcome>& runs, const std::vector<vf::SceneSpec>& specs) {
  Outcome all;
  double duration = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const double d = specs[i].duration;
    duration += d;
    all.cpuPerSimSecond += runs[i].cpuPerSimSecond * d;
    all.stepsPerSimSecond += runs[i].stepsPerSimSecond * d;
    all.awakePerSimSecond += runs[i].awakePerSimSecond * d;
    all.maxPenetration = std::max(all.maxPenetration, runs[i].maxPenetration);
  }
  all.cpuPerSimSecond /= duration;
  all.stepsPerSimSecond /= duration;
  all.awakePerSimSecond /= duration;
  return all;
}

int compare(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const Case cases[] = {{"cubes", "cubes", false, 1},
                        {"blocks", "blocks", false, 1},
                        {"stack", "stack", false, 1},
                        {"crosses", "crosses", false, 1},
                        {"crosses, Bullet compound", "crosses", true, 1},
                        {"cliff", "cliff", false, 1},
                        {"cliff, 20 throws", "cliff", false, 20}};
  std::printf(
      "| scene | voxfall Lv4 paper (ms/sim s) | voxfall Lv4 +reduction+sleep | ext + clearance "
      "step | Bullet 1/60 s | paper / Bullet | ext / Bullet | ext + clearance / Bullet | deepest: "
      "Bullet, voxfall paper, ext, ext + clearance (mm) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  std::vector<StepRow> stepRows;
  std::vector<RateRow> rateRows;
  for (const Case& k : cases) {
    std::vector<vf::SceneSpec> paper, ext, clear;
    for (int t = 0; t < k.throws; ++t) {
      paper.push_back(sceneAt(k.scene, 4, false));
      ext.push_back(sceneAt(k.scene, 4, true));
      clear.push_back(sceneAt(k.scene, 4, true, true));
      for (auto* spec : {&paper.back(), &ext.back(), &clear.back()})
        for (vf::EmitterSpec& e : spec->emitters) e.seed += static_cast<std::uint64_t>(t);
    }
    // Round 0 checks and records the spawns; every round times all five, interleaved.
    std::vector<std::vector<std::vector<Spawn>>> spawns(k.throws);
    Outcome pv, ev, cv, bb, bq;
    std::vector<double> tp, te, tc, tb, tq;
    int substeps = 1;  // Bullet's steps per 1/60 s at eq. 20's rate, set in round 0
    for (int r = 0; r < rounds; ++r) {
      const bool check = r == 0;
      std::vector<Outcome> p, e, c, b, q;
      for (int t = 0; t < k.throws; ++t)
        p.push_back(runVoxfall(paper[t], check, check ? &spawns[t] : nullptr));
      for (int t = 0; t < k.throws; ++t) e.push_back(runVoxfall(ext[t], check, nullptr));
      const Outcome oe = together(e, ext);
      if (check)
        substeps = std::max(1, static_cast<int>(std::lround(oe.stepsPerSimSecond * kFrame)));
      for (int t = 0; t < k.throws; ++t) c.push_back(runVoxfall(clear[t], check, nullptr));
      for (int t = 0; t < k.throws; ++t)
        b.push_back(runBullet(paper[t], spawns[t], check, k.compound));
      for (int t = 0; t < k.throws; ++t)
        q.push_back(runBullet(paper[t], spawns[t], check, k.compound, substeps));
      const Outcome op = together(p, paper), oc = together(c, clear), ob = together(b, paper),
                    oq = together(q, paper);
      if (check) pv = op, ev = oe, cv = oc, bb = ob, bq = oq;
      tp.push_back(op.cpuPerSimSecond);
      te.push_back(oe.cpuPerSimSecond);
      tc.push_back(oc.cpuPerSimSecond);
      tb.push_back(ob.cpuPerSimSecond);
      tq.push_back(oq.cpuPerSimSecond);
    }
    const double p = median(tp), e = median(te), c = median(tc), b = median(tb), q = median(tq);
    std::printf(
        "| %s | %.1f | %.1f | %.1f | %.1f | %.2fx | %.2fx | %.2fx | %.0f, %.1f, %.1f, %.1f |\n",
        k.label, 1e3 * p, 1e3 * e, 1e3 * c, 1e3 * b, p / b, e / b, c / b, 1e3 * bb.maxPenetration,
        1e3 * pv.maxPenetration, 1e3 * ev.maxPenetration, 1e3 * cv.maxPenetration);
    std::fflush(stdout);
    StepRow row{
        k.label,
        {pv.stepsPerSimSecond, ev.stepsPerSimSecond, cv.stepsPerSimSecond, bb.stepsPerSimSecond},
        {},
        {pv.awakePerSimSecond, ev.awakePerSimSecond, cv.awakePerSimSecond, bb.awakePerSimSecond}};
    const double times[4] = {p, e, c, b};
    for (int i = 0; i < 4; ++i) row.usPerStep[i] = 1e6 * times[i] / row.steps[i];
    stepRows.push_back(row);
    rateRows.push_back({k.label, substeps, ev.stepsPerSimSecond, bq.stepsPerSimSecond, e, q,
                        ev.maxPenetration, bq.maxPenetration});
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
  std::printf(
      "\n| scene | Bullet steps per 1/60 s | steps per simulated s: ext, Bullet | CPU ms per "
      "simulated s: ext, Bullet | ext / Bullet: time, per step | deepest (mm): ext, Bullet |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const RateRow& r : rateRows)
    std::printf("| %s | %d | %.0f, %.0f | %.1f, %.1f | %.2fx, %.2fx | %.1f, %.0f |\n",
                r.scene.c_str(), r.substeps, r.steps[0], r.steps[1], 1e3 * r.cpu[0], 1e3 * r.cpu[1],
                r.cpu[0] / r.cpu[1], (r.cpu[0] / r.steps[0]) / (r.cpu[1] / r.steps[1]),
                1e3 * r.deepest[0], 1e3 * r.deepest[1]);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return compare(argc, argv);
  } catch (const std::exception& e) {  // a scene that does not load, a wrong compound
    std::fprintf(stderr, "bullet_compare: error: %s\n", e.what());
    return 1;
  }
}
