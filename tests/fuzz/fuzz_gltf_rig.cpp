// libFuzzer harness for the glTF skin and animation paths (core/io/gltf_loader.h, core/character/animation.h,
// core/character/skinning.h): the input is loaded like fuzz_gltf's (".glb" when it starts with "glTF", else
// ".gltf"); when a character loads, every clip is sampled at a few times (before its start, at its
// keys' ends and between, looped and not) and the character skinned at each pose, its joint
// matrices and per-point joints computed: what the editor does every frame of playback.
#include <cstdlib>
#include <cstring>

#include "core/io/gltf_loader.h"
#include "core/character/skinning.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = cagewrap::fuzz::write_input(glb ? "in.glb" : "in.gltf", data, size);
  auto c = cagewrap::load_character(path);
  if (!c.ok()) {
    if (c.error().message.find(path) == std::string::npos) std::abort();  // errors name the file
    return 0;
  }
  if (c->num_vertices() > 65536 || c->skeleton.size() > 4096 || c->clips.size() > 64) return 0;  // keep it fast
  const cagewrap::PointJoints joints = cagewrap::point_joint_nodes(*c);
  if (joints.start.size() != c->num_vertices() + 1) std::abort();
  std::vector<glm::mat4> matrices;
  for (int32_t clip = -1; clip < static_cast<int32_t>(c->clips.size()); ++clip) {
    const double duration = clip < 0 ? 0.0 : c->clips[clip].duration;
    for (double t : {-1.0, 0.0, 0.37 * duration, duration, 2.5 * duration + 0.1}) {
      for (bool loop : {false, true}) {
        const cagewrap::Pose pose = cagewrap::sample_pose(*c, clip, t, loop);
        const std::vector<glm::mat4> globals = c->skeleton.global_transforms(pose);
        for (const cagewrap::Skin& skin : c->skins) {
          matrices.resize(skin.joints.size());
          cagewrap::joint_matrices(skin, globals, matrices);
        }
        const std::vector<glm::vec3> skinned = cagewrap::skin_character(*c, pose);
        if (skinned.size() != c->num_vertices()) std::abort();
      }
    }
  }
  return 0;
}
