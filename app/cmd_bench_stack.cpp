// cagewrap bench --project P [--clip C] [--changes N] [--json]: what a project's deformer stack costs
// (issue 21): each deformer that moves the skin bound and posed alone (its rig: deformer_document), then
// the whole stack's rig (Rig::create / Rig::pose of the project), and the combination alone
// (combine_stack); each parametric driver that moves the skin bound and displaced alone (DriverLayer). The stack's pose should cost the sum of its deformers' and a little more (the
// combination); the figure of record is the ratio, measured in the same run.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/base/stats.h"
#include "core/document/project_io.h"
#include "core/rig/deformer_stack.h"
#include "core/rig/driver_layer.h"
#include "core/rig/rig.h"

namespace cagewrap::app {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Timed {
  std::string name;
  double bind_s = 0.0, pose_ms = 0.0;
};

// Binds `doc` (timed) and poses it at `frames` times along the clip (the median pose time).
Result<Timed> time_rig(const Document& doc, std::string name, int32_t clip, uint32_t frames, std::vector<glm::vec3>& skin) {
  Timed t;
  t.name = std::move(name);
  const auto t0 = std::chrono::steady_clock::now();
  auto rig = Rig::create(doc);
  if (!rig) return rig.error();
  t.bind_s = seconds_since(t0);
  skin.resize(rig->num_skin_points());
  PosedCage cage;
  const double duration = doc.character->clips[static_cast<size_t>(clip)].duration;
  std::vector<double> ms;
  for (uint32_t f = 0; f <= frames; ++f) {  // the first pose warms up and is not counted
    const auto p0 = std::chrono::steady_clock::now();
    if (auto s = rig->pose_clip(doc, clip, duration * f / frames, {}, cage, skin); !s) return s.error();
    if (f > 0) ms.push_back(1000.0 * seconds_since(p0));
  }
  t.pose_ms = median(ms);
  return t;
}

// Parametric driver i bound alone (DriverLayer::create, timed) and its displacement made at `frames` times
// along the clip (the median; the skeleton's transforms included, as Rig makes them).
Result<Timed> time_driver(const Document& doc, size_t i, std::span<const glm::vec3> rest, int32_t clip, uint32_t frames) {
  Timed t;
  t.name = "D" + (i ? std::to_string(i + 1) : std::string()) + " " + driver_name(doc, i);
  const DriverRef r = driver_at(doc, i);
  const auto t0 = std::chrono::steady_clock::now();
  auto layer = DriverLayer::create(*doc.character, rest, *r.driver, driver_params(doc, *r.place), {}, r.place->set_edits);
  if (!layer) return layer.error();
  if (r.place->attachment)
    if (auto a = layer->attach(*doc.character, &*r.place->attachment); !a) return a.error();
  t.bind_s = seconds_since(t0);
  std::vector<glm::vec3> delta(rest.size());
  const double duration = doc.character->clips[static_cast<size_t>(clip)].duration;
  std::vector<double> ms;
  for (uint32_t f = 0; f <= frames; ++f) {
    const auto p0 = std::chrono::steady_clock::now();
    const Pose pose = compose_pose(*doc.character, clip, duration * f / frames, false, {});
    const std::vector<glm::mat4> globals = doc.character->skeleton.global_transforms(pose);
    if (auto s = layer->displacement(*r.driver, r.place->keyposes, doc.character->skeleton, pose, globals, delta); !s) return s.error();
    if (f > 0) ms.push_back(1000.0 * seconds_since(p0));
  }
  t.pose_ms = median(ms);
  return t;
}

}  // namespace

int bench_stack(const std::string& project, const std::string& clip_name, uint32_t frames, bool json) {
  auto loaded = load_project_or_report(project);
  if (!loaded) return 1;
  const Document& doc = loaded->document;
  if (!doc.cage) {
    std::fprintf(stderr, "error: %s: the project has no cage yet\n", project.c_str());
    return 1;
  }
  const int32_t clip = doc.character->find_clip(clip_name);
  if (clip < 0) {
    std::fprintf(stderr, "error: %s: no clip named or numbered '%s'\n", project.c_str(), clip_name.c_str());
    return 1;
  }
  // each deformer alone, then the stack
  std::vector<Timed> parts;
  std::vector<std::vector<glm::vec3>> skins;
  std::vector<size_t> which;
  for (size_t d = 0; d < deformer_count(doc); ++d) {
    if (deformer_muted(doc, d)) continue;
    skins.emplace_back();
    auto t = time_rig(deformer_document(doc, d), std::to_string(d) + " " + deformer_name(doc, d), clip, frames, skins.back());
    if (!t) {
      std::fprintf(stderr, "error: %s: deformer '%s': %s\n", project.c_str(), deformer_name(doc, d).c_str(), t.error().message.c_str());
      return 1;
    }
    parts.push_back(*t);
    which.push_back(d);
  }
  std::vector<glm::vec3> rest(doc.character->num_vertices());
  {
    size_t i = 0;
    for (const auto& prim : doc.character->primitives)
      for (const auto& p : prim.positions) rest[i++] = p;
  }
  for (size_t i = 0; i < driver_count(doc); ++i) {  // the parametric drivers that move the skin
    if (!driver_moves_skin(doc, i)) continue;
    auto t = time_driver(doc, i, rest, clip, frames);
    if (!t) {
      std::fprintf(stderr, "error: %s: parametric driver '%s': %s\n", project.c_str(), driver_name(doc, i).c_str(),
                   t.error().message.c_str());
      return 1;
    }
    parts.push_back(*t);
  }
  std::vector<glm::vec3> stack_skin;
  auto stack = time_rig(doc, "stack", clip, frames, stack_skin);
  if (!stack) {
    std::fprintf(stderr, "error: %s: %s\n", project.c_str(), stack.error().message.c_str());
    return 1;
  }
  // the combination alone (the editor's: core/rig/deformer_stack.h), on the last frame's skins
  const auto skin_of = [&](size_t d) -> const std::vector<glm::vec3>* {
    for (size_t k = 0; k < which.size(); ++k)
      if (which[k] == d) return &skins[k];
    return nullptr;
  };
  std::vector<double> combine_ms;
  for (uint32_t f = 0; f < frames; ++f) {
    std::vector<glm::vec3> out;
    const auto c0 = std::chrono::steady_clock::now();
    if (auto s = combine_document_stack(doc, rest, skin_of, out); !s) {
      std::fprintf(stderr, "error: %s: %s\n", project.c_str(), s.error().message.c_str());
      return 1;
    }
    combine_ms.push_back(1000.0 * seconds_since(c0));
  }
  double bind_sum = 0.0, pose_sum = 0.0;
  for (const Timed& t : parts) bind_sum += t.bind_s, pose_sum += t.pose_ms;
  const double combine = median(combine_ms);
  if (json) {
    nlohmann::json j;
    j["project"] = project;
    j["skin_points"] = stack_skin.size();
    j["mode"] = stack_mode_name(doc.stack.mode);
    j["frames"] = frames;
    for (const Timed& t : parts) j["deformers"].push_back({{"name", t.name}, {"bind_s", t.bind_s}, {"pose_ms", t.pose_ms}});
    j["sum"] = {{"bind_s", bind_sum}, {"pose_ms", pose_sum}};
    j["stack"] = {{"bind_s", stack->bind_s}, {"pose_ms", stack->pose_ms}, {"combine_ms", combine}};
    j["pose_ratio"] = pose_sum > 0 ? stack->pose_ms / pose_sum : 0.0;
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("stack of %s: %zu deformers moving the skin, %s, %zu skin points, clip '%s', %u poses each (median)\n",
              project.c_str(), parts.size(), stack_mode_name(doc.stack.mode), stack_skin.size(),
              doc.character->clips[size_t(clip)].name.c_str(), frames);
  std::printf("%-22s %10s %12s\n", "deformer", "bind s", "pose ms");
  for (const Timed& t : parts) std::printf("%-22s %10.3f %12.3f\n", t.name.c_str(), t.bind_s, t.pose_ms);
  std::printf("%-22s %10.3f %12.3f\n", "sum of the deformers", bind_sum, pose_sum);
  std::printf("%-22s %10.3f %12.3f  (of which combining %.3f ms)\n", "the stack", stack->bind_s, stack->pose_ms, combine);
  std::printf("stack / sum: bind %.2f, pose %.2f\n", bind_sum > 0 ? stack->bind_s / bind_sum : 0.0,
              pose_sum > 0 ? stack->pose_ms / pose_sum : 0.0);
  return 0;
}

}  // namespace cagewrap::app
