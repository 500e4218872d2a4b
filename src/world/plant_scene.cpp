#include "plant_scene.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <set>
#include <unordered_map>

#include "canopy/common/value_text.h"
#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/world/texture.h"

namespace canopy::world {

namespace fs = std::filesystem;

namespace {

std::string lower_case(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return e;
}

// Hash of a triangle by its exact vertex coordinates, in any vertex order.
struct TriangleKey {
  std::array<double, 9> v;
  bool operator==(const TriangleKey& o) const { return v == o.v; }
};
struct TriangleHash {
  size_t operator()(const TriangleKey& k) const {
    size_t h = 0;
    for (double d : k.v) h = h * 1000003u ^ std::hash<double>()(d);
    return h;
  }
};
TriangleKey triangle_key(const std::array<Vec3, 3>& t) {
  std::array<Vec3, 3> s = t;
  std::sort(s.begin(), s.end(), [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  TriangleKey k;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) k.v[static_cast<size_t>(3 * i + j)] = s[static_cast<size_t>(i)][j];
  return k;
}

std::string material_name(const aiScene* scene, unsigned index) {
  aiString name;
  if (scene->mMaterials[index]->Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length > 0) return name.C_Str();
  return "material_" + std::to_string(index);
}

// Largest texture file read [bytes].
constexpr std::uintmax_t kMaxTextureFileBytes = std::uintmax_t(256) << 20;

// Each material's diffuse colour (clamped to [0, 1]) and diffuse texture reference.
void read_diffuse(const aiScene* scene, std::vector<MaterialSoup>* soups) {
  for (unsigned i = 0; i < scene->mNumMaterials; ++i) {
    const aiMaterial* m = scene->mMaterials[i];
    MaterialSoup& s = (*soups)[i];
    aiColor4D c;
    if (m->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) {
      s.has_color = true;
      s.rgba[0] = std::clamp(c.r, 0.f, 1.f);
      s.rgba[1] = std::clamp(c.g, 0.f, 1.f);
      s.rgba[2] = std::clamp(c.b, 0.f, 1.f);
    }
    aiString texture;
    if (m->GetTextureCount(aiTextureType_DIFFUSE) > 0 && m->GetTexture(aiTextureType_DIFFUSE, 0, &texture) == AI_SUCCESS)
      s.texture_ref = texture.C_Str();
    s.has_texture = !s.texture_ref.empty();
  }
}

}  // namespace

PlantScene::PlantScene(const std::string& path) : path_(path), importer_(std::make_unique<Assimp::Importer>()) {
  std::error_code ec;
  if (!fs::is_regular_file(path_, ec)) throw InputError(path_ + ": no such file");
  importer_->SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Points and lines go to meshes of their own (SortByPType) and are counted and dropped
  // below; canopy applies node transforms and drops degenerate triangles itself.
  const aiScene* scene =
      importer_->ReadFile(path_, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
    std::string why = importer_->GetErrorString();
    for (char& c : why)
      if (c == '\n' || c == '\r') c = ' ';
    throw InputError(path_ + ": assimp cannot read it: " + (why.empty() ? std::string("incomplete scene") : why));
  }
  if (scene->mNumMeshes == 0) throw InputError(path_ + ": the file holds no mesh");
  scene_ = scene;
}

PlantScene::~PlantScene() = default;

std::string PlantScene::format() const {
  aiString f;
  if (scene_->mMetaData && scene_->mMetaData->Get("SourceAsset_Format", f)) return f.C_Str();
  return "";
}

// The file's own unit [m per unit]. assimp 5.2 bakes COLLADA's <unit meter> into the root
// node as a uniform scale (a visual_scene has no transform of its own), so it is read back
// from there; other formats carry no unit assimp reports (glTF is metres, OBJ unitless).
double PlantScene::file_unit_m() const {
  if (lower_case(format()).find("collada") == std::string::npos) return 1.0;
  const Eigen::Matrix4d R = to_eigen(scene_->mRootNode->mTransformation);
  const double s = R(0, 0);
  const Eigen::Matrix4d uniform = Eigen::Vector4d(s, s, s, 1.0).asDiagonal();
  if (!(s > 0.0) || (R - uniform).cwiseAbs().maxCoeff() > 1e-9 * s) return 1.0;
  // assimp holds it as a float; the file's decimal (0.0254, not 0.025399999693) is the
  // float printed to its 7 significant digits.
  char text[32];
  c_snprintf(text, sizeof(text), "%.7g", s);
  return c_strtod(text, nullptr);
}

std::string PlantScene::default_up() const {
  const std::string ext = lower_case(fs::path(path_).extension().string());
  return (ext == ".gltf" || ext == ".glb") ? "y" : "z";
}

std::vector<MaterialSoup> PlantScene::triangles_by_material(const Eigen::Matrix4d& T_out_file,
                                                             ImportReport* report) const {
  const aiScene* scene = scene_;
  std::vector<MaterialSoup> soups;
  soups.assign(scene->mNumMaterials, MaterialSoup{});
  for (unsigned i = 0; i < scene->mNumMaterials; ++i) soups[i].name = material_name(scene, i);
  std::unordered_map<TriangleKey, std::string, TriangleHash> first_node;
  std::set<std::string> pairs;
  std::function<void(const aiNode*, const Eigen::Matrix4d&)> walk = [&](const aiNode* node, const Eigen::Matrix4d& T_parent) {
    const Eigen::Matrix4d T = T_parent * to_eigen(node->mTransformation);
    const std::string node_name = node->mName.length ? node->mName.C_Str() : "(unnamed)";
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
      MaterialSoup& soup = soups[mesh->mMaterialIndex];
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) {
          ++report->non_triangles_dropped;
          continue;
        }
        std::array<Vec3, 3> t;
        FaceUv uv;
        const bool has_uv = mesh->HasTextureCoords(0);
        for (int c = 0; c < 3; ++c) {
          const aiVector3D& v = mesh->mVertices[face.mIndices[c]];
          t[static_cast<size_t>(c)] = (T * Eigen::Vector4d(v.x, v.y, v.z, 1.0)).head<3>();
          if (has_uv) {
            const aiVector3D& w = mesh->mTextureCoords[0][face.mIndices[c]];
            uv[static_cast<size_t>(c)] = Vec2(w.x, w.y);
          } else {
            uv[static_cast<size_t>(c)] = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
          }
        }
        soup.uv.push_back(uv);
        if (!has_uv) ++soup.without_uv;
        ++report->triangles_in;
        const auto [it, fresh] = first_node.try_emplace(triangle_key(t), node_name);
        soup.duplicate.push_back(!fresh);
        if (!fresh) {
          ++report->duplicate_triangles;
          pairs.insert(it->second + " = " + node_name);
        }
        soup.triangles.push_back(t);
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], T);
  };
  walk(scene->mRootNode, T_out_file);
  report->duplicate_nodes.assign(pairs.begin(), pairs.end());
  read_diffuse(scene, &soups);
  return soups;
}

std::optional<Image<Rgb8>> PlantScene::load_texture(const std::string& ref) const {
  if (const aiTexture* t = scene_->GetEmbeddedTexture(ref.c_str())) {
    const std::string what = path_ + ": embedded texture '" + ref + "'";
    if (t->mHeight == 0)  // compressed (PNG, JPEG, ...): mWidth bytes
      return decode_image(std::string(reinterpret_cast<const char*>(t->pcData), t->mWidth), what);
    if (t->mWidth > static_cast<unsigned>(kMaxTextureSidePx) || t->mHeight > static_cast<unsigned>(kMaxTextureSidePx))
      throw InputError(what + ": larger than " + std::to_string(kMaxTextureSidePx) + " px a side");
    Image<Rgb8> image(static_cast<int>(t->mWidth), static_cast<int>(t->mHeight));
    for (size_t i = 0; i < image.data.size(); ++i) image.data[i] = Rgb8{t->pcData[i].r, t->pcData[i].g, t->pcData[i].b};
    return image;
  }
  std::string rel = ref;
  std::replace(rel.begin(), rel.end(), '\\', '/');
  if (rel.rfind("file://", 0) == 0) rel = rel.substr(7);
  const fs::path dir = fs::path(path_).parent_path();
  std::vector<fs::path> candidates;
  if (fs::path(rel).is_absolute()) candidates.push_back(rel);
  else candidates.push_back(dir / rel);
  candidates.push_back(dir / fs::path(rel).filename());
  std::error_code ec;
  for (const auto& c : candidates)
    if (fs::is_regular_file(c, ec)) return decode_image(read_file(c.string(), kMaxTextureFileBytes), c.string());
  return std::nullopt;
}

}  // namespace canopy::world
