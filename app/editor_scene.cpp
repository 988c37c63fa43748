#include "app/editor_scene.h"

#include <unistd.h>

#include <filesystem>

#include "core/gltf_loader.h"
#include "core/mesh_io.h"
#include "core/project_io.h"
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
  if (!doc().cage) return false;
  if (!binding || bound_cage != doc().cage) return true;
  const BindParams& a = params;
  const BindParams& b = binding->params;
  return a.local != b.local || a.epsilon != b.epsilon || a.max_elements != b.max_elements || a.scale != b.scale ||
         a.max_distance != b.max_distance || a.variant != b.variant;
}

void Scene::start_bind() {
  if (!doc().cage || job) return;
  job = std::make_unique<BindJob>(skin_rest, *doc().cage, params);
  pending_cage_ = doc().cage;
}

void Scene::document_changed() {
  params = doc().params;
  const auto& cage = doc().cage;
  if (cage && (!attachment || attachment->joint.size() != cage->num_vertices() || attached_cage_ != cage)) {
    attachment.reset();
    if (!doc().character->skins.empty()) {
      auto att = attach_to_closest_limb(*doc().character, cage->polygons.positions);
      if (att) attachment = std::move(att).value();
    }
    attached_cage_ = cage;
  }
  if (!cage) {
    deformer.reset();
    binding.reset();
  }
  if (needs_rebind() && !job) start_bind();
}

Result<std::string> Scene::import_cage(const std::string& path) {
  auto mesh = load_mesh(path);
  if (!mesh) return mesh.error();
  auto cage = make_cage(std::move(mesh).value(), path);
  if (!cage) return cage.error();
  job.reset();  // a bind of the old cage: cancelled
  Document next = with_cage(doc(), std::make_shared<const Cage>(std::move(cage).value()));
  next = with_set_edits(with_cage_offsets(next, {}), {});
  history.push("Import cage " + std::filesystem::path(path).filename().string(), std::move(next));
  document_changed();
  return "imported cage " + path + " (" + std::to_string(doc().cage->num_vertices()) + " vertices)";
}

Document Scene::moved(const Document& from, std::span<const uint32_t> vertices, const glm::dvec3& world_delta) const {
  std::vector<glm::vec3> offsets = from.cage_offsets;
  offsets.resize(from.cage ? from.cage->num_vertices() : 0, glm::vec3(0.f));
  for (uint32_t v : vertices) {
    if (v >= offsets.size()) continue;
    // the offset lives in the bind space of the vertex's joint: undo the joint's linear part
    glm::dmat3 lin = v < cage_skinning.size() ? glm::dmat3(glm::mat3(cage_skinning[v])) : glm::dmat3(1.0);
    offsets[v] += glm::vec3(glm::inverse(lin) * world_delta);
  }
  return with_cage_offsets(from, std::move(offsets));
}

std::optional<std::string> Scene::poll_bind() {
  if (!job || !job->done()) return std::nullopt;
  auto& r = job->result();
  std::string message;
  if (r.ok()) {
    binding = std::make_unique<Binding>(std::move(r).value());
    bound_cage = pending_cage_;
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
  const Character& ch = *doc().character;
  Pose pose = sample_pose(ch, clip, player.time(), player.looping());
  std::vector<glm::mat4> globals = ch.skeleton.global_transforms(pose);
  joint_heads.resize(globals.size());
  for (size_t i = 0; i < globals.size(); ++i) joint_heads[i] = glm::vec3(globals[i][3]);
  bones.clear();
  for (size_t i = 0; i < ch.skeleton.size(); ++i)
    if (ch.skeleton.node(i).parent >= 0) bones.push_back({static_cast<uint32_t>(ch.skeleton.node(i).parent), static_cast<uint32_t>(i)});

  skin_from_cage = false;
  const auto& cage = doc().cage;
  if (cage) {
    // the driver at rest: the rest cage plus the artist's offsets
    std::vector<glm::vec3> driver_rest = cage->polygons.positions;
    for (size_t v = 0; v < doc().cage_offsets.size() && v < driver_rest.size(); ++v) driver_rest[v] += doc().cage_offsets[v];
    cage_posed.resize(cage->num_vertices());
    cage_linear.assign(cage->num_vertices(), glm::dmat3(1.0));
    cage_skinning.assign(cage->num_vertices(), glm::mat4(1.0f));
    if (attachment && !ch.skins.empty()) {
      std::vector<glm::mat4> skinning(ch.skins[attachment->skin].joints.size());
      joint_matrices(ch.skins[attachment->skin], globals, skinning);
      pose_cage(*attachment, skinning, driver_rest, cage_posed, cage_linear);
      for (size_t v = 0; v < cage_skinning.size(); ++v) cage_skinning[v] = skinning[attachment->joint[v]];
    } else {
      cage_posed = driver_rest;
    }
    if (deformer && bound_cage == cage) {
      skin_posed.resize(skin_rest.size());
      auto t0 = std::chrono::steady_clock::now();
      const bool frames = binding->params.variant == Variant::kExtended && attachment;
      auto s = deformer->deform(cage_posed, skin_posed, frames ? std::span<const glm::dmat3>(cage_linear)
                                                               : std::span<const glm::dmat3>());
      deform_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      skin_from_cage = s.ok();
    }
  }
  if (!skin_from_cage) skin_posed = skin_character(ch, pose);
}

namespace {
std::unique_ptr<Scene> make_scene(Document doc) {
  auto scene = std::make_unique<Scene>(std::move(doc));
  const Character& ch = *scene->doc().character;
  for (const auto& prim : ch.primitives) scene->skin_rest.insert(scene->skin_rest.end(), prim.positions.begin(), prim.positions.end());
  scene->skin_topology = combined_topology(ch);
  if (!ch.clips.empty()) {
    scene->clip = 0;
    scene->player = ClipPlayer(ch.clips[0].duration);
  }
  scene->document_changed();
  scene->update_pose();
  return scene;
}
}  // namespace

Result<std::unique_ptr<Scene>> load_scene(const std::string& character_path, const std::string& cage_path) {
  auto doc = document_from_files(character_path, cage_path);
  if (!doc) return doc.error();
  return make_scene(std::move(doc).value());
}

Result<std::unique_ptr<Scene>> load_project_scene(const std::string& project_path, std::vector<std::string>& warnings) {
  auto loaded = load_project(project_path);
  if (!loaded) return loaded.error();
  warnings.insert(warnings.end(), loaded->warnings.begin(), loaded->warnings.end());
  return make_scene(std::move(loaded->document));
}

std::string demo_cage_path(const std::string& character_path) {
  std::filesystem::path p = std::filesystem::path(character_path).parent_path() / "demo_cage.obj";
  return std::filesystem::exists(p) ? p.string() : std::string();
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
