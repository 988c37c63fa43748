// The cage rig as JSON for other tools (`cagewrap export --format json`; every field is described
// in docs/export-json.md): the cage at rest (positions, sculpted offsets, polygons, control
// triangles), how it follows the skeleton (the skin's joints by node name with their inverse bind
// matrices; per cage vertex the joints and weights the attachment actually uses, the mode and the
// overrides) and the keyposes, with node names beside node indices. With the character's glTF
// file this is enough to pose the driver cage exactly as core/rig/rig.h does:
//   D_v = (sum_i w_vi * global(node_vi) * inverse_bind_vi) * (positions_v + offsets_v + keyposes_v(pose)).
#pragma once

#include <string>

#include "core/cage/cage_attachment.h"
#include "core/document/document.h"
#include "core/base/result.h"

namespace cagewrap {

inline constexpr const char* kRigJsonFormat = "cagewrap-rig";
inline constexpr int kRigJsonVersion = 1;

struct RigJson {
  std::string text;  // UTF-8 JSON, ends with a newline
  size_t vertices = 0, faces = 0, keypose_sets = 0;
  bool attached = false;  // false: the character has no skin, the cage does not follow a skeleton
};

// Fails when the document has no cage, or its attachment fails (an override naming a node that is
// not a joint of the skin: the message names it).
// `attachment`: the rig's (a fitted attachment needs the binding, core/deform/attachment_fit.h); null: made
// from the document's settings (attach_cage: the transferred weights for a fitted attachment).
Result<RigJson> rig_json(const Document& doc, const CageAttachment* attachment = nullptr);

}  // namespace cagewrap
