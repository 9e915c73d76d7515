// World state -> what to draw: DrawListBuilder turns the poses of a run's frames into the plain
// draw data of render/draw_data.h (meshes, instances with model matrices and colours, the
// ground, the camera and the sun). Everything decided here (framing, colours, what casts
// shadows) is unit-testable without GL.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "render/auto_framing.h"
#include "render/draw_data.h"
#include "render/light.h"
#include "render/smooth_normals.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

class World;  // sim/world.h

// What the draw list needs from one body: a World-free view, so tests can build one directly.
struct BodyView {
  std::shared_ptr<const Shape> shape;
  Vec3 x = Vec3::Zero();      // centre of mass, m
  Quat q = Quat::Identity();  // body -> world
  bool active = true;         // released (emitters); inactive bodies are not drawn
  Color color{0.8f, 0.8f, 0.8f};
  // Crease angle in degrees for smooth shading (creasedNormals); none: every face flat.
  std::optional<double> smoothDegrees;
};

// The bodies of a world with their colours; a body without a colour in `colors` gets
// defaultBodyColor(id).
std::vector<BodyView> bodyViews(const World& world, const std::vector<Color>& colors);

// Model matrix of a body: rotation R(q) and translation x.
Mat4 bodyModelMatrix(const Vec3& x, const Quat& q);

// Terrains of more than twice this many triangles are drawn in tiles of about this many.
constexpr std::size_t kTerrainTileTriangles = 8192;

// Builds draw lists frame after frame for one run. Holds what persists between frames: the
// camera settings, the terrain, the per-shape radii, the region the automatic camera has to
// frame and the one the shadow map covers (every body position observe()d so far: both only
// grow), and per observed frame the bodies' centres (trails) and the chase camera's smoothed
// target. `voxfall render` observes every frame of the scene, in order from frame 0, before
// drawing any, and then calls build(bodies, k): the automatic camera and the shadow map hold
// still for the whole clip, and frame k (its trails and its chase camera, which depend on
// frames 0..k) looks the same whatever range is rendered. A lone build(bodies) observes its
// bodies as the next frame and draws that.
class DrawListBuilder {
 public:
  // For frames of width x height pixels, `fps` drawn frames per simulated second (frame k at
  // t = k / fps; at [output] speed X, the output's fps / X).
  DrawListBuilder(const CameraSpec& camera, std::optional<double> groundHeight, int width,
                  int height, double fps);
  // The same for an aspect ratio width / height, 720 pixels high, 30 frames per second.
  DrawListBuilder(const CameraSpec& camera, std::optional<double> groundHeight, double aspect);

  // A terrain as the solid it is: its surface with smooth normals, its sides and base
  // (terrain_solid.h), the picture draped on it (none: slope colours) and its heights, which
  // turn the automatic and chase cameras across its slope (terrain_camera.h).
  void setTerrain(std::shared_ptr<const Heightfield> field,
                  std::shared_ptr<const DrapeImage> drape = nullptr);
  // A static terrain mesh in world coordinates, drawn with slope shading and casting shadows.
  // It is not part of the automatic framing (see observe()). A large one is drawn as tiles,
  // one instance each (kTerrainTileTriangles), so that a partial redraw draws only the tiles
  // it can touch; each triangle keeps its vertices and normals, so the pixels are the same.
  void setTerrain(std::shared_ptr<const TriMesh> mesh,
                  std::shared_ptr<const std::vector<Vec3>> normals = nullptr,
                  Color color = Color{0.16f, 0.22f, 0.09f});

  // The terrain's surface as drawn (world coordinates); null without a terrain.
  const std::shared_ptr<const TriMesh>& terrainSurface() const { return terrain_; }
  // Its vertex normals (smooth), one per vertex of terrainSurface(); null without them.
  const std::shared_ptr<const std::vector<Vec3>>& terrainSurfaceNormals() const {
    return terrainNormals_;
  }
  // The sides and base of the terrain's solid (terrainSides), drawn lit in an earth colour and
  // casting shadows.
  void setTerrainSides(std::shared_ptr<const TriMesh> sides);
  // The scene's light (sceneLight). Without a sun direction, the default one for the automatic
  // camera's view (defaultSunDirection): fixed once the first frame is included.
  void setLight(const SceneLight& light);
  // The automatic camera's horizontal viewing direction: defaultAutoView(), or across the
  // terrain's slope under the first included frame's bodies.
  const Vec3& autoView() const { return autoView_; }

  // Folds the next frame's active bodies into the automatic framing and records the frame's
  // body centres and chase target. Frames are observed in order, starting at frame 0.
  void observe(std::span<const BodyView> bodies) {
    include(bodies);
    addDrawnFrame(bodies);
  }
  // The two halves of observe(), for playbacks whose drawn frames are not the frames that set
  // the framing (time remapping: the scene's own frames frame the shot whatever the speed).
  // include(): folds active bodies into the automatic framing and the shadow map's region.
  void include(std::span<const BodyView> bodies);
  // addDrawnFrame(): records the next drawn frame's body centres (trails) and chase target.
  void addDrawnFrame(std::span<const BodyView> bodies);
  // The draw list of observed frame `frame` drawn with these bodies (its poses).
  DrawList build(std::span<const BodyView> bodies, int frame);
  // Observes the bodies as the next frame and draws it.
  DrawList build(std::span<const BodyView> bodies);
  // Frames observed so far.
  int observedFrames() const { return static_cast<int>(history_.size()); }

  // Whether a body is still on the stage: on the terrain's extent (or anywhere over a floor
  // plane) and not wholly below the lowest ground. Bodies that left it are still drawn, but
  // neither the automatic camera nor the shadow map makes room for them.
  bool onStage(const BodyView& body);

  // Radius of a shape's mesh about its centre of mass (m), cached per shape.
  double shapeRadius(const std::shared_ptr<const Shape>& shape);

 private:
  // Turns the automatic view across the terrain's slope under these bodies (the first frame).
  void chooseAutoView(std::span<const BodyView> bodies);
  // A chase on a terrain without a given offset, which frames across the slope.
  bool terrainChase() const;
  // The automatic camera for the frames observed so far (worked out once for them).
  CameraView automaticCamera();
  // What a body is drawn with: its shape's mesh, or that mesh split for smooth shading.
  DrawMesh bodyMesh(const BodyView& body);
  std::vector<Sphere> bodySpheres(std::span<const BodyView> bodies, bool withGround);
  // The chase camera's target this frame: the followed body or the group's centroid (active
  // bodies only); none when nothing is followed or all followed bodies are inactive.
  std::optional<Vec3> chaseTarget(std::span<const BodyView> bodies) const;
  // The view of observed frame `frame`: path, fixed or chase (scene's view), chase (framed), or
  // the automatic framing.
  CameraView chooseCamera(std::span<const BodyView> bodies, int frame);
  // Trails: each body's centre over the last trailSeconds up to `frame`, as a ribbon about
  // kTrailPixels wide facing the camera, unlit in the body's colour.
  void addTrails(DrawList& list, std::span<const BodyView> bodies, int frame);
  // build()'s parts: the active bodies' meshes and instances, seen by list.camera; the
  // terrain's tiles and sides; the sphere the shadow map covers (every body position observed
  // and the terrain); the floor's fade and the camera's depth range, from the distance to what
  // the camera looks at and the framed region's radius `extent`.
  void addBodies(DrawList& list, std::span<const BodyView> bodies);
  void addTerrain(DrawList& list) const;
  Sphere casterSphere() const;
  void setDepthRange(DrawList& list, const Sphere& region, double distance, double extent) const;

  // What one observed frame leaves for later draws.
  struct FrameRecord {
    std::vector<Vec3> centres;  // per body id
    std::vector<bool> active;
    std::optional<Vec3> chase;  // smoothed chase target
    // A chase on a terrain: its horizontal viewing direction, across the slope under the
    // target, turning smoothly (kChaseTurnSeconds in draw_list.cpp).
    Vec3 chaseView = Vec3::Zero();
  };

  CameraSpec spec_;
  std::optional<double> ground_;
  double aspect_;
  int height_ = 720;  // pixels
  double fps_ = 30;
  std::vector<FrameRecord> history_;
  AutoFraming framing_;
  Eigen::AlignedBox3d casterBox_;  // around every on-stage body of every observed frame
  // Keyed by address; the shared_ptr keeps the shape alive so an address is never reused.
  std::map<const Shape*, std::pair<std::shared_ptr<const Shape>, double>> radii_;
  std::shared_ptr<const TriMesh> terrain_;
  std::shared_ptr<const std::vector<Vec3>> terrainNormals_;
  // The terrain as drawn: tiles of it (setTerrain in draw_list.cpp), or the whole mesh.
  struct TerrainTile {
    std::shared_ptr<const TriMesh> mesh;
    std::shared_ptr<const std::vector<Vec3>> normals;
  };
  std::vector<TerrainTile> terrainTiles_;
  Color terrainColor_{};
  Sphere terrainSphere_;
  Eigen::AlignedBox3d terrainBox_;
  std::shared_ptr<const Heightfield> field_;
  std::shared_ptr<const TriMesh> terrainSides_;
  Sphere sidesSphere_;
  int included_ = 0;  // frames folded into the framing so far
  // The automatic camera, for this many included and observed frames.
  std::optional<std::pair<std::pair<int, int>, CameraView>> autoCamera_;
  std::shared_ptr<const DrapeImage> drape_;
  SceneLight light_;
  Vec3 autoView_;
  // Smooth-shaded meshes per shape and crease angle, made once.
  std::map<std::pair<const Shape*, double>, std::shared_ptr<const CreasedMesh>> creased_;
};

}  // namespace vf
