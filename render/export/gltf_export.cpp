// The animation as an aiScene, exported by Assimp::Exporter to "glb2" in memory and written
// through an OutputFile. Meshes are shared: one per shape and colour, which every node of such
// a body references (assimp exports a node's mesh index as it is). Node extras are the one
// thing assimp 5.2's exporter drops, so the georeference is added to the GLB's JSON chunk
// afterwards (GLB layout: glTF 2.0 specification, section 4.4).
#include "render/export/gltf_export.h"

#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Exporter.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>

#include "render/image.h"
#include "render/output/png_writer.h"
#include "sim/core/error.h"

namespace vf {
namespace {

aiVector3D toAi(const Vec3& v) {
  return aiVector3D(static_cast<float>(v.x()), static_cast<float>(v.y()),
                    static_cast<float>(v.z()));
}

aiFace triangleFace(unsigned a, unsigned b, unsigned c) {
  aiFace face;
  face.mNumIndices = 3;
  face.mIndices = new unsigned[3]{a, b, c};
  return face;
}

// A body's mesh with flat normals, as voxfall draws bodies: every triangle has its own three
// vertices carrying its unit face normal (+z for a degenerate one, which has none).
aiMesh* flatMesh(const TriMesh& mesh, unsigned material, const std::string& name) {
  auto* m = new aiMesh();
  m->mName = aiString(name);
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mMaterialIndex = material;
  m->mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  m->mNumVertices = 3 * m->mNumFaces;
  m->mVertices = new aiVector3D[m->mNumVertices];
  m->mNormals = new aiVector3D[m->mNumVertices];
  m->mFaces = new aiFace[m->mNumFaces];
  for (unsigned f = 0; f < m->mNumFaces; ++f) {
    const auto& t = mesh.triangles[f];
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 cross = (b - a).cross(c - a);
    const double area = cross.norm();
    const aiVector3D normal = toAi(area > 0 ? Vec3(cross / area) : Vec3::UnitZ());
    for (unsigned k = 0; k < 3; ++k) {
      m->mVertices[3 * f + k] = toAi(mesh.vertices[t[k]]);
      m->mNormals[3 * f + k] = normal;
    }
    m->mFaces[f] = triangleFace(3 * f, 3 * f + 1, 3 * f + 2);
  }
  return m;
}

// A mesh with shared vertices and the given per-vertex normals (the terrain, smooth).
aiMesh* smoothMesh(const TriMesh& mesh, const std::vector<Vec3>& normals, unsigned material,
                   const std::string& name, const DrapeImage* drape) {
  VF_ASSERT(normals.size() == mesh.vertices.size());
  auto* m = new aiMesh();
  m->mName = aiString(name);
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mMaterialIndex = material;
  m->mNumVertices = static_cast<unsigned>(mesh.vertices.size());
  m->mVertices = new aiVector3D[m->mNumVertices];
  m->mNormals = new aiVector3D[m->mNumVertices];
  for (unsigned i = 0; i < m->mNumVertices; ++i) {
    m->mVertices[i] = toAi(mesh.vertices[i]);
    m->mNormals[i] = toAi(normals[i]);
  }
  m->mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  m->mFaces = new aiFace[m->mNumFaces];
  for (unsigned f = 0; f < m->mNumFaces; ++f) {
    const auto& t = mesh.triangles[f];
    m->mFaces[f] = triangleFace(t[0], t[1], t[2]);
  }
  if (drape) {
    // The renderer's drape lookup (shaders/scene.frag): a world point's texel is at
    // ((x - x0) / (x1 - x0), (y - y0) / (y1 - y0)) of the image from its south-west corner.
    // assimp keeps v upwards from the image's last row, as OpenGL does, and its glTF exporter
    // writes 1 - v, glTF's downwards from the first row (the north edge, see drapePicture).
    m->mNumUVComponents[0] = 2;
    m->mTextureCoords[0] = new aiVector3D[m->mNumVertices];
    const double w = drape->x1 - drape->x0, h = drape->y1 - drape->y0;
    for (unsigned i = 0; i < m->mNumVertices; ++i) {
      const Vec3& p = mesh.vertices[i];
      m->mTextureCoords[0][i] = aiVector3D(static_cast<float>((p.x() - drape->x0) / w),
                                           static_cast<float>((p.y() - drape->y0) / h), 0.0f);
    }
  }
  return m;
}

// The sRGB transfer function and its inverse (IEC 61966-2-1), on values in [0, 1].
double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
double linearToSrgb(double c) {
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

// The drape as an opaque picture, north row first: each texel laid over `under` (linear RGB)
// by its coverage, mixed in linear light as the renderer mixes it over its slope colours, since
// a glTF material's texture has no second colour to show where the raster has no data.
Image drapePicture(const DrapeImage& d, const Color& under) {
  Image out(d.width, d.height);
  for (int row = 0; row < d.height; ++row)
    for (int col = 0; col < d.width; ++col) {
      const std::uint8_t* in = d.rgba.data() + 4 * (static_cast<std::size_t>(row) * d.width + col);
      std::uint8_t* px = out.pixel(col, d.height - 1 - row);  // DrapeImage: row 0 is south
      const double a = in[3] / 255.0;
      for (int k = 0; k < 3; ++k) {
        const double c = in[k] / 255.0;
        const double mixed = a == 1 ? c : linearToSrgb(a * srgbToLinear(c) + (1 - a) * under[k]);
        px[k] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(mixed, 0.0, 1.0)));
      }
    }
  return out;
}

// The drape as assimp's embedded texture "*0": a PNG, whose bytes the glTF exporter stores in
// the GLB's binary chunk.
aiTexture* embeddedPng(const DrapeImage& d, const Color& under, const std::string& where) {
  const std::vector<std::uint8_t> png =
      encodePng(drapePicture(d, under), PngCompression::small, where);
  auto* texture = new aiTexture();
  texture->mWidth = static_cast<unsigned>(png.size());  // mHeight 0: compressed, mWidth bytes
  texture->mHeight = 0;
  texture->pcData = new aiTexel[(png.size() + sizeof(aiTexel) - 1) / sizeof(aiTexel)];
  std::memcpy(texture->pcData, png.data(), png.size());
  std::strcpy(texture->achFormatHint, "png");
  texture->mFilename = aiString("terrain_texture.png");
  return texture;
}

aiMaterial* toAiMaterial(const Color& c, const std::string& name) {
  auto* material = new aiMaterial();
  const aiString materialName(name);
  material->AddProperty(&materialName, AI_MATKEY_NAME);
  const aiColor4D colour(c[0], c[1], c[2], 1.0f);  // linear RGB, as glTF's baseColorFactor
  material->AddProperty(&colour, 1, AI_MATKEY_BASE_COLOR);
  material->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
  return material;
}

// The meshes a scene needs: one per shape and colour in order of first use by body id, and
// which one each body's node references.
struct MeshPlan {
  struct Entry {
    const BodyView* body;  // the first body of this shape and colour
    std::string name;      // its shape's name
  };
  std::vector<Entry> meshes;
  std::vector<unsigned> ofBody;
};

MeshPlan planMeshes(const std::vector<BodyView>& bodies, const std::vector<std::string>& names) {
  MeshPlan plan;
  std::map<std::pair<const Shape*, Color>, unsigned> index;
  for (std::size_t id = 0; id < bodies.size(); ++id) {
    const BodyView& b = bodies[id];
    const auto [it, added] = index.emplace(std::make_pair(b.shape.get(), b.color),
                                           static_cast<unsigned>(plan.meshes.size()));
    if (added) plan.meshes.push_back({&b, id < names.size() ? names[id] : "body"});
    plan.ofBody.push_back(it->second);
  }
  return plan;
}

// One key per frame per body, at tick k with fps ticks per second (t = k / fps).
aiNodeAnim* bodyChannel(const AnimationExport& a, std::size_t body, const aiString& node) {
  const unsigned keys = static_cast<unsigned>(a.frames.size());
  auto* ch = new aiNodeAnim();
  ch->mNodeName = node;
  ch->mNumPositionKeys = ch->mNumRotationKeys = ch->mNumScalingKeys = keys;
  ch->mPositionKeys = new aiVectorKey[keys];
  ch->mRotationKeys = new aiQuatKey[keys];
  ch->mScalingKeys = new aiVectorKey[keys];
  for (unsigned k = 0; k < keys; ++k) {
    const BodyView& v = a.frames[k][body];
    const double t = k;
    ch->mPositionKeys[k] = aiVectorKey(t, toAi(v.x));
    const Quat q = v.q.normalized();
    ch->mRotationKeys[k] =
        aiQuatKey(t, aiQuaternion(static_cast<float>(q.w()), static_cast<float>(q.x()),
                                  static_cast<float>(q.y()), static_cast<float>(q.z())));
    const float s = v.active ? 1.0f : 0.0f;  // not yet released: hidden
    ch->mScalingKeys[k] = aiVectorKey(t, aiVector3D(s, s, s));
  }
  return ch;
}

std::uint32_t read32(const std::string& s, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, s.data() + at, 4);  // GLB is little-endian, as every platform voxfall runs on
  return v;
}

void put32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

// The GLB with `extras` set on the scene's root node. The JSON chunk is replaced (padded with
// spaces to 4 bytes, as the format asks); the binary chunk is kept byte for byte.
std::string withRootExtras(const std::string& glb, const nlohmann::ordered_json& extras,
                           const std::string& path) {
  constexpr std::uint32_t kJson = 0x4E4F534A;  // "JSON"
  if (glb.size() < 20 || read32(glb, 16) != kJson)
    throw InputError(path, "glTF export failed: assimp wrote no GLB JSON chunk");
  const std::uint32_t jsonLength = read32(glb, 12);
  auto json = nlohmann::ordered_json::parse(glb.substr(20, jsonLength));
  const std::size_t root = json.at("scenes").at(0).at("nodes").at(0).get<std::size_t>();
  json.at("nodes").at(root)["extras"] = extras;
  std::string text = json.dump();
  text.append((4 - text.size() % 4) % 4, ' ');
  const std::string rest = glb.substr(20 + jsonLength);  // the binary chunk, whole
  std::string out = glb.substr(0, 8);                    // magic and version
  put32(out, static_cast<std::uint32_t>(12 + 8 + text.size() + rest.size()));
  put32(out, static_cast<std::uint32_t>(text.size()));
  put32(out, kJson);
  return out + text + rest;
}

// The meshes and materials of `scene`: one per entry of `plan`, then the terrain (with its
// draped picture embedded as a PNG texture) when the export has one.
void addMeshes(aiScene& scene, const AnimationExport& a, const MeshPlan& plan,
               const std::string& path) {
  const unsigned bodyMeshes = static_cast<unsigned>(plan.meshes.size());
  const unsigned meshes = bodyMeshes + (a.terrain ? 1 : 0);
  scene.mNumMeshes = meshes;
  scene.mMeshes = new aiMesh*[meshes];
  scene.mNumMaterials = meshes;
  scene.mMaterials = new aiMaterial*[meshes];
  for (unsigned i = 0; i < bodyMeshes; ++i) {
    const MeshPlan::Entry& e = plan.meshes[i];
    scene.mMeshes[i] = flatMesh(e.body->shape->mesh, i, e.name);
    scene.mMaterials[i] = toAiMaterial(e.body->color, e.name);
  }
  if (!a.terrain) return;
  VF_ASSERT(a.terrainNormals != nullptr);
  const DrapeImage* drape = a.terrainTexture.get();
  scene.mMeshes[bodyMeshes] =
      smoothMesh(*a.terrain, *a.terrainNormals, bodyMeshes, "terrain", drape);
  const Color terrainColour{0.16f, 0.22f, 0.09f};
  if (drape) {
    // glTF multiplies the texture by the base colour: white shows the picture as it is.
    scene.mMaterials[bodyMeshes] = toAiMaterial(Color{1, 1, 1}, "terrain");
    const aiString embedded("*0");
    scene.mMaterials[bodyMeshes]->AddProperty(&embedded, AI_MATKEY_TEXTURE_DIFFUSE(0));
    scene.mNumTextures = 1;
    scene.mTextures = new aiTexture* [1] { embeddedPng(*drape, terrainColour, path) };
  } else {
    scene.mMaterials[bodyMeshes] = toAiMaterial(terrainColour, "terrain");
  }
}

// The root node (z-up turned y-up) with one child per body, named by bodyNodeName, and the
// terrain's last.
void addNodes(aiScene& scene, const AnimationExport& a, const MeshPlan& plan, unsigned bodies) {
  const unsigned nodes = bodies + (a.terrain ? 1 : 0);
  // Names are glTF ids in assimp's exporter: the root must not share the animation's name.
  scene.mRootNode = new aiNode("world");
  aiNode& root = *scene.mRootNode;
  // z-up -> y-up: rows give (x, z, -y).
  root.mTransformation = aiMatrix4x4(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1);
  root.mNumChildren = nodes;
  root.mChildren = new aiNode*[nodes];
  for (unsigned i = 0; i < nodes; ++i) {
    const bool terrain = i == bodies;
    const unsigned mesh = terrain ? static_cast<unsigned>(plan.meshes.size()) : plan.ofBody[i];
    auto* node = new aiNode(
        terrain ? std::string("terrain")
                : bodyNodeName(i < a.shapeNames.size() ? a.shapeNames[i] : std::string("body"),
                               static_cast<int>(i)));
    node->mParent = &root;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{mesh};
    root.mChildren[i] = node;
  }
}

// The animation: one channel per body, a key per frame.
void addAnimation(aiScene& scene, const AnimationExport& a, unsigned bodies) {
  auto* anim = new aiAnimation();
  anim->mName = aiString(a.name.empty() ? std::string("voxfall") : a.name);
  anim->mTicksPerSecond = a.fps;
  anim->mDuration = static_cast<double>(a.frames.size() - 1);
  anim->mNumChannels = bodies;
  anim->mChannels = new aiNodeAnim*[bodies];
  for (unsigned b = 0; b < bodies; ++b)
    anim->mChannels[b] = bodyChannel(a, b, scene.mRootNode->mChildren[b]->mName);
  scene.mNumAnimations = 1;
  scene.mAnimations = new aiAnimation* [1] { anim };
}

// The scene as GLB bytes, with the DEM's georeference in the root node's extras when given.
std::string exportGlb(const aiScene& scene, const AnimationExport& a, const std::string& path) {
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, "glb2");
  if (blob == nullptr)
    throw InputError(path, std::string("glTF export failed: ") + exporter.GetErrorString());
  std::string glb;
  for (const aiExportDataBlob* b = blob; b != nullptr; b = b->next)
    glb.append(static_cast<const char*>(b->data), b->size);
  if (a.georeference) {
    const DemGeoreference& g = *a.georeference;
    nlohmann::ordered_json extras;
    extras["crs"] = g.crs;
    extras["crs_wkt"] = g.crsWkt;
    extras["dem_offset"] = {g.offset.x(), g.offset.y(), g.offset.z()};
    glb = withRootExtras(glb, extras, path);
  }
  return glb;
}

}  // namespace

std::string bodyNodeName(const std::string& shape, int id) {
  return shape + "_" + std::to_string(id);
}

void writeGltfAnimation(const std::string& path, const AnimationExport& a,
                        const OutputRules& rules) {
  VF_ASSERT(!a.frames.empty() && a.fps > 0);
  OutputFile out(path, rules);
  const std::vector<BodyView>& first = a.frames.front();
  const unsigned bodies = static_cast<unsigned>(first.size());
  const MeshPlan plan = planMeshes(first, a.shapeNames);
  aiScene scene;  // its destructor frees everything below
  addMeshes(scene, a, plan, path);
  addNodes(scene, a, plan, bodies);
  addAnimation(scene, a, bodies);
  const std::string glb = exportGlb(scene, a, path);
  if (std::fwrite(glb.data(), 1, glb.size(), out.stream()) != glb.size())
    throw InputError(path, "cannot write the glTF file");
  out.commit();
}

}  // namespace vf
