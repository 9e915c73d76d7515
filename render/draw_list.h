// World state -> what to draw, as plain data (no GL): meshes, instances with model matrices
// and colours, the ground, the camera and the sun. The renderer reads a DrawList and nothing
// else, so everything decided here (framing, colours, what casts shadows) is unit-testable.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "render/auto_framing.h"
#include "render/camera.h"
#include "render/light.h"
#include "render/smooth_normals.h"
#include "sim/scene/scene.h"
#include "sim/shape/drape_import.h"
#include "sim/shape/heightfield.h"
#include "sim/world.h"

namespace vf {

// A triangle mesh to draw, shared, not copied: the renderer uploads each key once.
struct DrawMesh {
  const void* key = nullptr;            // identity in the GPU cache: the Shape, or the terrain
  std::shared_ptr<const TriMesh> mesh;  // body frame (centre of mass at the origin) or world
  std::shared_ptr<const std::vector<Vec3>> normals;  // per-vertex smooth normals; null: faceted
  bool transient = false;  // made for this frame only (trails): uploaded, drawn, dropped
  // Back faces never seen, so they are culled: a closed surface wound outward (a body's shape)
  // seen from outside, or a terrain's walls and base, wound outward, whose insides lie under
  // its surface. llvmpipe shades every rasterised fragment, hidden or not, so they would cost
  // as much as the faces seen.
  bool closed = false;
};

// How an instance is shaded.
enum class Surface {
  body,     // colour lit by sun (with shadow), sky and fill light
  terrain,  // as body, with the colour turned towards rock on steep slopes
  unlit,    // the flat colour, no light, no shadow (overlays and read-back tests)
};

struct DrawInstance {
  int mesh = 0;                   // index into DrawList::meshes
  Mat4 model = Mat4::Identity();  // mesh frame -> world: [R(q) x; 0 1] for a body
  Color color{0.8f, 0.8f, 0.8f};  // linear RGB albedo
  Surface surface = Surface::body;
  bool castsShadow = true;
  // Identity across frames (the body id), so a frame can be compared with the last one when
  // bodies appear or leave; -1 for the rest (terrain, trails), matched by their order.
  int id = -1;
};

struct DrawList {
  std::vector<DrawMesh> meshes;
  std::vector<DrawInstance> instances;
  std::optional<double> groundHeight;  // z of the floor plane, m; none: no floor drawn
  CameraView camera;
  Vec3 sunDirection = Vec3(0.3, -0.4, 0.87).normalized();  // unit, towards the sun
  LightColors light;  // sun, sky and ambient light (render/light.h)
  // A picture draped on the instances with Surface::terrain (world x, y to texel by its
  // rectangle); null: they are coloured by slope.
  std::shared_ptr<const DrapeImage> drape;
  // Sphere around everything that casts a shadow: what the shadow map has to cover.
  Vec3 casterCentre = Vec3::Zero();
  double casterRadius = 1;
  // The floor fades into the sky between these distances from the camera (m); its grid
  // lines are 1 m apart with 0.1 m minor lines, so the picture shows scale.
  double groundFadeStart = 20;
  double groundFadeEnd = 60;
};

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

// What the GPU receives of a model matrix: the matrix and the one for normals (the inverse
// transpose of its linear part), both in single precision. Two model matrices with equal
// GpuTransforms draw the same pixels, however their doubles differ (a body at rest creeping
// by 1e-12 m).
struct GpuTransform {
  Eigen::Matrix4f model;
  Eigen::Matrix3f normal;
  bool operator==(const GpuTransform& o) const { return model == o.model && normal == o.normal; }
};
GpuTransform gpuTransform(const Mat4& model);

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
