// Part labels for automatic separation (BindParams::separate, PartLabels in core/deform/registration.h)
// from a character's skeleton: spatially close but unrelated parts (the two thighs, an arm hanging
// against the torso) should not pull on each other, which the paper leaves to the user (section 5,
// Figure 5). Labels are the skeleton's nodes, related through its hierarchy: each skin point takes
// its dominant joint (largest skin weight; a point of an unskinned primitive, the node that
// instances it), each cage vertex the joint it follows (core/cage/cage_attachment.h).
#pragma once

#include "core/cage/cage_attachment.h"
#include "core/character/character.h"
#include "core/character/part_relation.h"
#include "core/deform/registration.h"

namespace cagewrap {

// Points in skin_character order (#sum V), cage vertices as in `attachment` (#Vc). The labels'
// `related` relation is part_relation(character).
// Errors: a character without skeleton nodes, an attachment naming joints its skin does not have.
Result<PartLabels> skeleton_part_labels(const Character& character, const CageAttachment& attachment);

}  // namespace cagewrap
