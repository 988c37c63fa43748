// Characters read through assimp (core/io/assimp_loader.h, issue 23): for every skinned, animated model of
// assimp-testmodels (/usr/share/assimp/models, or $CAGEWRAP_ASSIMP_MODELS; skipped with a message when absent),
// cagewrap's linear blend skinning at several clip times equals the skinning computed here from assimp's own
// data (each bone's offset matrix applied to its node's global transform, the animation keys interpolated
// here), within 1e-5 of the diagonal; units and axes conversion is a scale and a turn of that.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include "core/character/skinning.h"
#include "core/io/assimp_loader.h"
#include "core/io/gltf_loader.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;

std::string models_dir() {
  if (const char* env = std::getenv("CAGEWRAP_ASSIMP_MODELS"); env && *env) return env;
  return "/usr/share/assimp/models";
}

glm::dmat4 to_glm(const aiMatrix4x4& m) {
  glm::dmat4 g;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) g[c][r] = m[r][c];
  return g;
}

// A key track at time t (seconds; keys in ticks): linear, clamped.
template <class Key, class F>
auto sample_keys(const Key* keys, unsigned n, double ticks, F lerp) {
  if (n == 1 || ticks <= keys[0].mTime) return keys[0].mValue;
  for (unsigned k = 0; k + 1 < n; ++k)
    if (ticks <= keys[k + 1].mTime) {
      const double u = (ticks - keys[k].mTime) / std::max(1e-12, keys[k + 1].mTime - keys[k].mTime);
      return lerp(keys[k].mValue, keys[k + 1].mValue, u);
    }
  return keys[n - 1].mValue;
}

// The reference: assimp's scene skinned at `seconds` into animation `a`, every mesh of every node, in the
// loader's order (nodes depth first, each node's meshes in order).
std::vector<glm::dvec3> assimp_skinned(const aiScene* s, unsigned a, double seconds) {
  const aiAnimation* anim = s->mAnimations[a];
  const double tps = anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 25.0;
  const double ticks = seconds * tps;
  std::map<std::string, glm::dmat4> local;
  for (unsigned c = 0; c < anim->mNumChannels; ++c) {
    const aiNodeAnim* ch = anim->mChannels[c];
    const aiNode* node = s->mRootNode->FindNode(ch->mNodeName);
    if (!node) continue;
    aiVector3D ns, nt;
    aiQuaternion nq;
    node->mTransformation.Decompose(ns, nq, nt);
    auto lerp3 = [](const aiVector3D& x, const aiVector3D& y, double u) { return x + (y - x) * float(u); };
    auto slerp = [](const aiQuaternion& x, const aiQuaternion& y, double u) {
      aiQuaternion out;
      aiQuaternion::Interpolate(out, x, y, float(u));
      return out.Normalize();
    };
    const aiVector3D t = ch->mNumPositionKeys ? sample_keys(ch->mPositionKeys, ch->mNumPositionKeys, ticks, lerp3) : nt;
    const aiQuaternion q = ch->mNumRotationKeys ? sample_keys(ch->mRotationKeys, ch->mNumRotationKeys, ticks, slerp) : nq;
    const aiVector3D sc = ch->mNumScalingKeys ? sample_keys(ch->mScalingKeys, ch->mNumScalingKeys, ticks, lerp3) : ns;
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(t.x, t.y, t.z)) * glm::mat4_cast(glm::dquat(q.w, q.x, q.y, q.z)) *
                   glm::scale(glm::dmat4(1.0), glm::dvec3(sc.x, sc.y, sc.z));
    local[ch->mNodeName.C_Str()] = m;
  }
  std::map<std::string, glm::dmat4> global;
  std::vector<glm::dvec3> out;
  std::function<void(const aiNode*, const glm::dmat4&)> walk = [&](const aiNode* n, const glm::dmat4& parent) {
    auto it = local.find(n->mName.C_Str());
    const glm::dmat4 g = parent * (it != local.end() ? it->second : to_glm(n->mTransformation));
    global[n->mName.C_Str()] = g;
    for (unsigned c = 0; c < n->mNumChildren; ++c) walk(n->mChildren[c], g);
  };
  walk(s->mRootNode, glm::dmat4(1.0));
  std::function<void(const aiNode*)> meshes = [&](const aiNode* n) {
    for (unsigned k = 0; k < n->mNumMeshes; ++k) {
      const aiMesh* m = s->mMeshes[n->mMeshes[k]];
      if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      std::vector<glm::dvec3> p(m->mNumVertices, glm::dvec3(0.0));
      if (!m->mNumBones) {
        for (unsigned v = 0; v < m->mNumVertices; ++v)
          p[v] = glm::dvec3(global[n->mName.C_Str()] * glm::dvec4(m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z, 1.0));
      } else {
        std::vector<double> total(m->mNumVertices, 0.0);
        for (unsigned b = 0; b < m->mNumBones; ++b) {
          const aiBone* bone = m->mBones[b];
          if (!global.count(bone->mName.C_Str())) continue;  // a bone of no node: left out, as the loader does
          const glm::dmat4 j = global[bone->mName.C_Str()] * to_glm(bone->mOffsetMatrix);
          for (unsigned w = 0; w < bone->mNumWeights; ++w) {
            const aiVertexWeight& vw = bone->mWeights[w];
            const aiVector3D& x = m->mVertices[vw.mVertexId];
            p[vw.mVertexId] += double(vw.mWeight) * glm::dvec3(j * glm::dvec4(x.x, x.y, x.z, 1.0));
            total[vw.mVertexId] += vw.mWeight;
          }
        }
        // a vertex left with no weight is bound to the skin's first joint (the first bone with a node), as every
        // loader does
        glm::dmat4 first(1.0);
        for (unsigned b = 0; b < m->mNumBones; ++b)
          if (global.count(m->mBones[b]->mName.C_Str())) {
            first = global[m->mBones[b]->mName.C_Str()] * to_glm(m->mBones[b]->mOffsetMatrix);
            break;
          }
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
          const aiVector3D& x = m->mVertices[v];
          if (total[v] > 0) p[v] /= total[v];
          else p[v] = glm::dvec3(first * glm::dvec4(x.x, x.y, x.z, 1.0));
        }
      }
      out.insert(out.end(), p.begin(), p.end());
    }
    for (unsigned c = 0; c < n->mNumChildren; ++c) meshes(n->mChildren[c]);
  };
  meshes(s->mRootNode);
  return out;
}

TEST(AssimpLoader, SkinnedAnimatedTestModelsMatchAssimpsOwnSkinning) {
  const fs::path dir = models_dir();
  if (!fs::is_directory(dir)) GTEST_SKIP() << dir << " is absent: install assimp-testmodels (scripts/setup.sh)";
  size_t checked = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string path = entry.path().string();
    if (!entry.is_regular_file() || !is_assimp_character(path) || path.find("/invalid/") != std::string::npos) continue;
    Assimp::Importer importer;
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    const aiScene* s = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
    if (!s || !s->mNumAnimations) continue;
    bool bones = false;
    for (unsigned m = 0; m < s->mNumMeshes; ++m) bones = bones || s->mMeshes[m]->mNumBones > 0;
    if (!bones) continue;
    CharacterLoadOptions keep;
    keep.keep_units = true;
    AssimpUnits units;
    auto c = load_character_assimp(path, keep, &units);
    ASSERT_TRUE(c.ok()) << c.error().message;
    // assimp scales a Collada scene's root by its <unit>, which keep_units leaves out
    std::string ext = fs::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    const double unit = ext == ".dae" ? units.metres_per_unit : 1.0;
    ASSERT_FALSE(c->clips.empty()) << path;
    const std::vector<glm::vec3> rest = skin_character(*c, c->skeleton.rest_pose());
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& p : rest) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double diagonal = unit * glm::length(hi - lo);
    const double duration = c->clips[0].duration;
    double worst = 0.0;
    for (double f : {0.0, 0.3, 0.55, 1.0}) {
      const double t = f * duration;
      const std::vector<glm::vec3> ours = skin_character(*c, sample_pose(*c, 0, t));
      const std::vector<glm::dvec3> ref = assimp_skinned(s, 0, t);
      ASSERT_EQ(ours.size(), ref.size()) << path;
      for (size_t v = 0; v < ours.size(); ++v) worst = std::max(worst, glm::length(unit * glm::dvec3(ours[v]) - ref[v]));
    }
    std::printf("%s: %zu vertices, %zu joints, clip '%s' %.3g s: worst %.3g (diagonal %.3g)\n", path.c_str(), rest.size(),
                c->num_joints(), c->clips[0].name.c_str(), duration, worst, diagonal);
    EXPECT_LE(worst, 1e-5 * diagonal) << path;
    ++checked;
  }
  EXPECT_GT(checked, 2u) << "skinned, animated models found in " << dir;
}

TEST(AssimpLoader, UnitsAndUpAxisAreAScaleAndATurn) {
  const std::string path = models_dir() + "/FBX/animation_with_skeleton.fbx";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent: install assimp-testmodels (scripts/setup.sh)";
  AssimpUnits units;
  auto converted = load_character_assimp(path, {}, &units);
  ASSERT_TRUE(converted.ok()) << converted.error().message;
  CharacterLoadOptions keep;
  keep.keep_units = true;
  auto kept = load_character_assimp(path, keep);
  ASSERT_TRUE(kept.ok()) << kept.error().message;
  std::printf("%s: %g m a unit, %s up, converted %d\n", path.c_str(), units.metres_per_unit, units.up_axis.c_str(), int(units.converted));
  const std::vector<glm::vec3> a = skin_character(*converted, sample_pose(*converted, 0, 0.2));
  const std::vector<glm::vec3> b = skin_character(*kept, sample_pose(*kept, 0, 0.2));
  ASSERT_EQ(a.size(), b.size());
  // a = s R b for the file's scale s and the turn R of its up axis to +Y: the distances scale by s
  double ratio_lo = 1e30, ratio_hi = 0;
  for (size_t v = 1; v < a.size(); v += std::max<size_t>(1, a.size() / 50)) {
    const double da = glm::length(a[v] - a[0]), db = glm::length(b[v] - b[0]);
    if (db > 1e-6) {
      ratio_lo = std::min(ratio_lo, da / db);
      ratio_hi = std::max(ratio_hi, da / db);
    }
  }
  EXPECT_NEAR(ratio_lo, units.metres_per_unit, 1e-4 * units.metres_per_unit);
  EXPECT_NEAR(ratio_hi, units.metres_per_unit, 1e-4 * units.metres_per_unit);
}

TEST(AssimpLoader, BadFilesAreNamed) {
  const fs::path dir = fs::temp_directory_path() / "cagewrap_assimp_bad";
  fs::create_directories(dir);
  const std::string fbx = (dir / "garbage.fbx").string();
  { FILE* f = std::fopen(fbx.c_str(), "wb"); std::fputs("this is not an FBX file at all", f); std::fclose(f); }
  auto r = load_character(fbx);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message.rfind(fbx + ": ", 0), 0u) << r.error().message;
  auto missing = load_character((dir / "nothing.dae").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("no such file"), std::string::npos) << missing.error().message;
}

}  // namespace
}  // namespace cagewrap

namespace cagewrap {
namespace {

// The bounding box of a character's rest skin.
std::pair<glm::vec3, glm::vec3> rest_box(const Character& c) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : skin_character(c, c.skeleton.rest_pose())) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return {lo, hi};
}

// Collada's <unit> and <up_axis>, which assimp applies and does not report, are read from the file: an inch, Z-up
// file comes in metres, Y up; with keep_units, in inches, Z up; the raw positions agree with the rest skinning.
TEST(AssimpLoader, ColladaUnitAndUpAxisAreReadAndApplied) {
  const std::string path = models_dir() + "/Collada/kwxport_test_vcolors.dae";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent: install assimp-testmodels (scripts/setup.sh)";
  AssimpUnits units, kept_units;
  auto converted = load_character_assimp(path, {}, &units);
  ASSERT_TRUE(converted.ok()) << converted.error().message;
  CharacterLoadOptions keep;
  keep.keep_units = true;
  auto kept = load_character_assimp(path, keep, &kept_units);
  ASSERT_TRUE(kept.ok()) << kept.error().message;
  EXPECT_NEAR(units.metres_per_unit, 0.0254, 1e-12);
  EXPECT_EQ(units.up_axis, "+Z");
  EXPECT_TRUE(units.converted);
  EXPECT_FALSE(kept_units.converted);
  const auto [clo, chi] = rest_box(*converted);
  const auto [klo, khi] = rest_box(*kept);
  // the file's Z extent (in inches) is the converted Y extent (in metres); X stays X
  EXPECT_NEAR(chi.y - clo.y, 0.0254 * (khi.z - klo.z), 1e-4 * (chi.y - clo.y));
  EXPECT_NEAR(chi.x - clo.x, 0.0254 * (khi.x - klo.x), 1e-4 * (chi.x - clo.x));
  bool warned = false;
  for (const std::string& w : converted->warnings) warned = warned || w.find("brought to metres, Y up") != std::string::npos;
  EXPECT_TRUE(warned) << "the conversion is reported";
}

// A converted scene is in metres throughout: the raw positions (the bind pose every tool reads) and the rest pose's
// skinning agree, for a centimetre FBX.
TEST(AssimpLoader, ConvertedBindPoseAgreesWithTheRestSkinning) {
  const std::string path = models_dir() + "/FBX/huesitos.fbx";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent: install assimp-testmodels (scripts/setup.sh)";
  AssimpUnits units;
  auto c = load_character_assimp(path, {}, &units);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_NEAR(units.metres_per_unit, 0.01, 1e-9);
  std::vector<glm::vec3> raw;
  for (const Primitive& p : c->primitives) raw.insert(raw.end(), p.positions.begin(), p.positions.end());
  const std::vector<glm::vec3> rest = skin_character(*c, c->skeleton.rest_pose());
  ASSERT_EQ(raw.size(), rest.size());
  const auto [lo, hi] = rest_box(*c);
  double worst = 0.0;
  for (size_t v = 0; v < raw.size(); ++v) worst = std::max(worst, double(glm::length(raw[v] - rest[v])));
  std::printf("%s: rest skin vs raw positions worst %.3g m (diagonal %.3g m)\n", path.c_str(), worst, double(glm::length(hi - lo)));
  EXPECT_LE(worst, 1e-4 * glm::length(hi - lo));
}

// A character's meshes bound together share one skin, as a glTF character's do (the cage follows one skin): the
// torso, head and legs of BCN_Epileptic.X, whose bones are disjoint; the skinning is still assimp's (the test above).
TEST(AssimpLoader, MeshesBoundTogetherShareOneSkin) {
  const std::string path = models_dir() + "/X/BCN_Epileptic.X";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent: install assimp-testmodels (scripts/setup.sh)";
  auto c = load_character(path);
  ASSERT_TRUE(c.ok()) << c.error().message;
  ASSERT_EQ(c->primitives.size(), 3u);
  EXPECT_EQ(c->skins.size(), 1u);
  for (const Primitive& p : c->primitives) EXPECT_EQ(p.skin, 0) << p.mesh_name;
  EXPECT_EQ(c->skins[0].joints.size(), c->skins[0].inverse_bind.size());
  for (const std::string& w : c->warnings) EXPECT_EQ(w.find("another pose"), std::string::npos) << w;
}

// A file on which Open Asset Import itself crashes (an MD5 mesh fuzz_assimp made from SimpleCube.md5mesh) is an
// error naming the file and the crash: the importer runs in a child process, and this one carries on.
TEST(AssimpLoader, AFileThatCrashesTheImporterIsAnError) {
  const fs::path input = fs::path(CAGEWRAP_SOURCE_DIR) / "tests/fuzz/corpus/assimp/md5-that-crashes-assimp";
  ASSERT_TRUE(fs::exists(input)) << input;
  const fs::path dir = fs::temp_directory_path() / "cagewrap_assimp_crash";
  fs::create_directories(dir);
  const std::string path = (dir / "cut.md5mesh").string();
  fs::copy_file(input, path, fs::copy_options::overwrite_existing);
  auto r = load_character(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message.rfind(path + ": ", 0), 0u) << r.error().message;
  EXPECT_NE(r.error().message.find("crashed"), std::string::npos) << r.error().message;
  // and the next file reads as usual
  const std::string good = models_dir() + "/X/Testwuson.X";
  if (fs::exists(good)) EXPECT_TRUE(load_character(good).ok());
}

// A character read from memory (a project's embedded FBX) is the one read from the file.
TEST(AssimpLoader, BytesInMemoryReadAsTheFile) {
  const std::string path = models_dir() + "/X/Testwuson.X";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent: install assimp-testmodels (scripts/setup.sh)";
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto from_file = load_character(path);
  auto from_bytes = load_character_bytes(bytes, "embedded Testwuson.X", {}, path);
  ASSERT_TRUE(from_file.ok()) << from_file.error().message;
  ASSERT_TRUE(from_bytes.ok()) << from_bytes.error().message;
  ASSERT_EQ(from_file->num_vertices(), from_bytes->num_vertices());
  ASSERT_EQ(from_file->clips.size(), from_bytes->clips.size());
  const auto a = skin_character(*from_file, sample_pose(*from_file, 1, 0.5));
  const auto b = skin_character(*from_bytes, sample_pose(*from_bytes, 1, 0.5));
  for (size_t v = 0; v < a.size(); ++v) ASSERT_EQ(a[v], b[v]) << "vertex " << v;
  auto bad = load_character_bytes("not a DirectX file", "embedded bad.x", {}, "bad.x");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message.rfind("embedded bad.x: ", 0), 0u) << bad.error().message;
}

}  // namespace
}  // namespace cagewrap
