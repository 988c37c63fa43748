#include "app/editor_scene.h"

#include <unistd.h>

#include <filesystem>

#include "core/gltf_loader.h"
#include "core/mesh_io.h"
#include "core/skinning.h"

namespace cagewrap::app {

BindJob::BindJob(std::vector<glm::vec3> skin, Cage cage, BindParams params)
    : skin_(std::move(skin)), cage_(std::move(cage)), params_(params) {
  thread_ = std::thread([this] {
    BindProgress p;
    p.on_progress = [this](double f) { progress_ = f; };
    p.cancel = &cancel_;
    result_.emplace(bind_skin(skin_, cage_, cage_.polygons.positions, params_, {}, p));
    done_ = true;
  });
}

BindJob::~BindJob() {
  cancel_ = true;
  if (thread_.joinable()) thread_.join();
}

bool Scene::needs_rebind() const {
  if (!cage) return false;
  if (!binding) return true;
  const BindParams& a = params;
  const BindParams& b = bound_params;
  return a.local != b.local || a.epsilon != b.epsilon || a.max_elements != b.max_elements || a.scale != b.scale ||
         a.max_distance != b.max_distance || a.variant != b.variant;
}

void Scene::start_bind() {
  if (!cage || job) return;
  job = std::make_unique<BindJob>(skin_rest, *cage, params);
}

std::optional<std::string> Scene::poll_bind() {
  if (!job || !job->done()) return std::nullopt;
  auto& r = job->result();
  std::string message;
  if (r.ok()) {
    binding = std::make_unique<Binding>(std::move(r).value());
    bound_params = binding->params;
    auto d = Deformer::create(*binding, skin_rest);
    if (d.ok()) {
      deformer.emplace(std::move(d).value());
      char buf[256];
      std::snprintf(buf, sizeof buf, "bound %u points to %zu elements in %.2f s (%zu skipped elements, %zu fallback points, quality %.1f%%)",
                    binding->num_points, binding->elements.size(), binding->seconds, binding->invalid_elements.size(),
                    binding->rigid_points.size(), 100 * binding->quality());
      message = buf;
    } else {
      message = "error: " + d.error().message;
    }
  } else {
    message = r.error().code == ErrorCode::kCancelled ? "bind cancelled" : "error: " + r.error().message;
  }
  job.reset();
  return message;
}

void Scene::update_pose() {
  const Character& ch = *character;
  Pose pose = sample_pose(ch, clip, player.time(), player.looping());
  std::vector<glm::mat4> globals = ch.skeleton.global_transforms(pose);
  joint_heads.resize(globals.size());
  for (size_t i = 0; i < globals.size(); ++i) joint_heads[i] = glm::vec3(globals[i][3]);
  bones.clear();
  for (size_t i = 0; i < ch.skeleton.size(); ++i)
    if (ch.skeleton.node(i).parent >= 0) bones.push_back({static_cast<uint32_t>(ch.skeleton.node(i).parent), static_cast<uint32_t>(i)});

  skin_from_cage = false;
  if (cage && attachment && !ch.skins.empty()) {
    std::vector<glm::mat4> skinning(ch.skins[attachment->skin].joints.size());
    joint_matrices(ch.skins[attachment->skin], globals, skinning);
    cage_posed.resize(cage->num_vertices());
    cage_linear.resize(cage->num_vertices());
    pose_cage(*attachment, skinning, cage->polygons.positions, cage_posed, cage_linear);
    if (deformer) {
      skin_posed.resize(skin_rest.size());
      auto t0 = std::chrono::steady_clock::now();
      const bool frames = binding->params.variant == Variant::kExtended;
      auto s = deformer->deform(cage_posed, skin_posed, frames ? std::span<const glm::dmat3>(cage_linear)
                                                               : std::span<const glm::dmat3>());
      deform_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      skin_from_cage = s.ok();
    }
  } else if (cage) {
    cage_posed = cage->polygons.positions;
  }
  if (!skin_from_cage) skin_posed = skin_character(ch, pose);
}

Result<std::unique_ptr<Scene>> load_scene(const std::string& character_path, const std::string& cage_path) {
  auto ch = load_character(character_path);
  if (!ch) return ch.error();
  auto scene = std::make_unique<Scene>();
  scene->character = std::make_shared<const Character>(std::move(ch).value());
  scene->skin_rest.clear();
  for (const auto& prim : scene->character->primitives)
    scene->skin_rest.insert(scene->skin_rest.end(), prim.positions.begin(), prim.positions.end());
  scene->skin_topology = combined_topology(*scene->character);
  if (!cage_path.empty()) {
    auto m = load_mesh(cage_path);
    if (!m) return m.error();
    auto c = make_cage(std::move(m).value(), cage_path);
    if (!c) return c.error();
    scene->cage = std::move(c).value();
    scene->cage_source = cage_path;
  }
  if (scene->cage && !scene->character->skins.empty()) {
    auto att = attach_to_closest_limb(*scene->character, scene->cage->polygons.positions);
    if (att) scene->attachment = std::move(att).value();
  }
  if (!scene->character->clips.empty()) {
    scene->clip = 0;
    scene->player = ClipPlayer(scene->character->clips[0].duration);
  }
  scene->update_pose();
  return scene;
}

std::string demo_character_path() {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  char exe[4096];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    exe[n] = 0;
    fs::path dir = fs::path(exe).parent_path();
    candidates.push_back(dir / "assets/demo_character.glb");
    candidates.push_back(dir.parent_path() / "assets/demo_character.glb");
  }
#ifdef CAGEWRAP_SOURCE_DIR_FOR_ASSETS
  candidates.push_back(fs::path(CAGEWRAP_SOURCE_DIR_FOR_ASSETS) / "assets/demo_character.glb");
#endif
  for (const auto& c : candidates)
    if (fs::exists(c)) return c.string();
  return {};
}

}  // namespace cagewrap::app
