// The animation as an aiScene, exported by Assimp::Exporter to "glb2" in memory and written
// through an OutputFile. One mesh per body (not per shape) because a glTF mesh carries its
// material, and each body has its own colour.
#include "render/export/gltf_export.h"

#include <assimp/scene.h>

#include <assimp/Exporter.hpp>
#include <cstdio>
#include <memory>

#include "sim/core/error.h"

namespace vf {
namespace {

aiMesh* toAiMesh(const TriMesh& mesh, unsigned material) {
  auto* m = new aiMesh();
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mMaterialIndex = material;
  m->mNumVertices = static_cast<unsigned>(mesh.vertices.size());
  m->mVertices = new aiVector3D[m->mNumVertices];
  for (unsigned i = 0; i < m->mNumVertices; ++i) {
    const Vec3& v = mesh.vertices[i];
    m->mVertices[i] =
        aiVector3D(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
  }
  m->mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  m->mFaces = new aiFace[m->mNumFaces];
  for (unsigned f = 0; f < m->mNumFaces; ++f) {
    aiFace& face = m->mFaces[f];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3];
    for (int c = 0; c < 3; ++c) face.mIndices[c] = static_cast<unsigned>(mesh.triangles[f][c]);
  }
  return m;
}

aiMaterial* toAiMaterial(const Color& c) {
  auto* material = new aiMaterial();
  const aiColor4D colour(c[0], c[1], c[2], 1.0f);  // linear RGB, as glTF's baseColorFactor
  material->AddProperty(&colour, 1, AI_MATKEY_BASE_COLOR);
  material->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
  return material;
}

}  // namespace

void writeGltfAnimation(const std::string& path, const AnimationExport& a,
                        const OutputRules& rules) {
  VF_ASSERT(!a.frames.empty() && a.fps > 0);
  OutputFile out(path, rules);
  const std::vector<BodyView>& first = a.frames.front();
  const unsigned bodies = static_cast<unsigned>(first.size());
  const unsigned meshes = bodies + (a.terrain ? 1 : 0);

  aiScene scene;  // its destructor frees everything below
  scene.mNumMeshes = meshes;
  scene.mMeshes = new aiMesh*[meshes];
  scene.mNumMaterials = meshes;
  scene.mMaterials = new aiMaterial*[meshes];
  // Names are glTF ids in assimp's exporter: the root must not share the animation's name.
  scene.mRootNode = new aiNode("world");
  aiNode& root = *scene.mRootNode;
  // z-up -> y-up: rows give (x, z, -y).
  root.mTransformation = aiMatrix4x4(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1);
  root.mNumChildren = meshes;
  root.mChildren = new aiNode*[meshes];
  for (unsigned i = 0; i < meshes; ++i) {
    const bool terrain = i == bodies;
    scene.mMeshes[i] = toAiMesh(terrain ? *a.terrain : first[i].shape->mesh, i);
    scene.mMaterials[i] = toAiMaterial(terrain ? Color{0.16f, 0.22f, 0.09f} : first[i].color);
    auto* node = new aiNode(terrain ? std::string("terrain") : "body_" + std::to_string(i));
    node->mParent = &root;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{i};
    root.mChildren[i] = node;
  }

  // One key per frame per body, at tick k with fps ticks per second (t = k / fps).
  auto* anim = new aiAnimation();
  anim->mName = aiString(a.name.empty() ? std::string("voxfall") : a.name);
  anim->mTicksPerSecond = a.fps;
  const unsigned keys = static_cast<unsigned>(a.frames.size());
  anim->mDuration = keys - 1;
  anim->mNumChannels = bodies;
  anim->mChannels = new aiNodeAnim*[bodies];
  for (unsigned b = 0; b < bodies; ++b) {
    auto* ch = new aiNodeAnim();
    ch->mNodeName = root.mChildren[b]->mName;
    ch->mNumPositionKeys = ch->mNumRotationKeys = ch->mNumScalingKeys = keys;
    ch->mPositionKeys = new aiVectorKey[keys];
    ch->mRotationKeys = new aiQuatKey[keys];
    ch->mScalingKeys = new aiVectorKey[keys];
    for (unsigned k = 0; k < keys; ++k) {
      const BodyView& v = a.frames[k][b];
      const double t = k;
      ch->mPositionKeys[k] =
          aiVectorKey(t, aiVector3D(static_cast<float>(v.x.x()), static_cast<float>(v.x.y()),
                                    static_cast<float>(v.x.z())));
      const Quat q = v.q.normalized();
      ch->mRotationKeys[k] =
          aiQuatKey(t, aiQuaternion(static_cast<float>(q.w()), static_cast<float>(q.x()),
                                    static_cast<float>(q.y()), static_cast<float>(q.z())));
      const float s = v.active ? 1.0f : 0.0f;  // not yet released: hidden
      ch->mScalingKeys[k] = aiVectorKey(t, aiVector3D(s, s, s));
    }
    anim->mChannels[b] = ch;
  }
  scene.mNumAnimations = 1;
  scene.mAnimations = new aiAnimation* [1] { anim };

  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, "glb2");
  if (blob == nullptr)
    throw InputError(path, std::string("glTF export failed: ") + exporter.GetErrorString());
  for (const aiExportDataBlob* b = blob; b != nullptr; b = b->next)
    if (std::fwrite(b->data, 1, b->size, out.stream()) != b->size)
      throw InputError(path, "cannot write the glTF file");
  out.commit();
}

}  // namespace vf
