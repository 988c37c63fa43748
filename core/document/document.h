// The artist's work as a value: which character, the rest cage, the binding parameters and the
// set edits. Copying a Document is cheap: the big immutable data (the character, the cage) sits
// behind shared_ptr<const T> and is replaced, never mutated, so undo snapshots share it
// (goxel's image_history_push; Blender's BKE_undo_system memory-capped steps).
// View state (camera, selection, current clip and time, panel layout) is not part of a Document.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/binding.h"
#include "core/cage/cage.h"
#include "core/io/gltf_loader.h"
#include "core/cage/cage_attachment.h"
#include "core/cage/cage_sim.h"
#include "core/character/character.h"
#include "core/cage/keyposes.h"
#include "core/deform/patch_surface.h"
#include "core/base/result.h"

namespace cagewrap {

// What a binding depends on, each as a content hash ("fnv1a64:<hex>"; core/document/binding_cache.h makes
// them): a cached binding is used only when every one matches the document.
struct BindingInputs {
  std::string program;     // the program and binding format that made it
  std::string character;   // the character file's content hash
  std::string cage;        // rest cage topology and positions, bit for bit
  std::string params;      // every binding parameter
  std::string set_edits;
  std::string attachment;  // the attachment settings (the part labels of automatic separation)

  bool operator==(const BindingInputs&) const = default;
};

// The binding cache a project file records (docs/project-format.md, "binding_cache").
struct BindingCacheRecord {
  std::string file;       // the .cwb file, absolute; "" = nothing cached
  std::string file_hash;  // content hash of the .cwb file's bytes when it was written
  BindingInputs inputs;   // what it was made from

  bool operator==(const BindingCacheRecord&) const = default;
};

// A deformer of the skin beyond the document's own cage (issue 21, docs/deformer-stack.md): a cage
// of its own (a fine face or hand cage, a garment cage) with everything the document's cage has (its
// binding parameters, set edits, sculpted offsets, attachment to the skeleton, keyposes, simulation),
// a name, an optional skin mask and a mute switch.
struct DeformerLayer {
  std::string name;
  std::shared_ptr<const Cage> cage;  // never null in a document
  BindParams params;
  std::vector<SetEdit> set_edits;
  std::vector<glm::vec3> cage_offsets;  // #Vc or empty
  AttachmentSettings attachment;
  std::vector<KeyposeSet> keyposes;
  SimSettings sim;
  // How much it may move each skin point, in [0, 1] (#P, skin_character order); null = all of it.
  std::shared_ptr<const std::vector<float>> mask;
  std::string mask_source;  // how the mask was made ("joints head,neck"; "" = none or painted)
  bool muted = false;       // left out of the stack (kept in the project)
  bool hidden = false;      // its cage not drawn in the editor (a view setting, saved with the project)
  // Its binding cached beside the project (P.cagewrap.<d>.cwb; core/document/binding_cache.h), when
  // the document caches bindings (Document::cache_binding): deformer_document puts it in the view's binding_cache.
  BindingCacheRecord binding_cache;
};

// How the deformers' results make the skin (docs/deformer-stack.md). f_0 is the document's own cage,
// f_i layer i's posed skin, m_i its mask, p the rest skin:
//   kInOrder: s = f_0; then for each layer s += m_i (f_i - s)   (each later layer takes over where its mask is 1)
//   kSum:     s = p + sum_i m_i (f_i - p)                        (displacements summed, f_0 with mask 1)
//   kBlend:   Wires (Singh & Fiume): the displacements d_i = m_i (f_i - p) blended with exponent m
//             (core/deform/deformer.h combine_displacements, in double)
enum class StackMode : uint8_t { kInOrder, kSum, kBlend };
struct DeformerStack {
  StackMode mode = StackMode::kInOrder;
  double exponent = 2.0;  // kBlend's m (>= 0)
  // Deformers are numbered 0 (the document's own cage) to layers.size() (layer k - 1).
  bool base_muted = false;   // the document's cage left out: its skin is the rest skin (f_0 = p)
  bool base_hidden = false;  // its cage not drawn in the editor
  int32_t solo = -1;         // only this deformer moves the skin (the others as if muted); -1 = none
  // The name of the only parametric driver that moves the skin (every cage as if muted: the rest skin
  // and its displacement); "" = none. At most one of `solo` and it is set.
  std::string solo_driver;
  bool operator==(const DeformerStack&) const = default;
};
const char* stack_mode_name(StackMode mode);               // "in_order", "sum", "blend"

// The parametric driver as a deformer of the stack (issue 21, docs/deformer-stack.md): where it sits,
// which skin points it may move and its keyposes. Its sculpt (the posed control points minus the rest
// ones, plus the keyposes' offsets at the pose, in bind space) is carried by the skeleton and gives a
// displacement of the skin (core/rig/driver_layer.h), scaled per point by the mask. Its on/off switch
// is PatchDriver::drive_skin; a soloed deformer leaves it out like the others.
struct DriverPlacement {
  // Its name in the deformer list and messages; "" = "driver".
  std::string name;
  // How many of the document's layers come before it: 0 = right after the document's cage, so that
  // every layer may take over its region; -1 (or more than there are) = after them all, as projects
  // before this field had it. Only kInOrder has an order: sum and blend add the driver's displacement
  // to the combined skin.
  int32_t after = -1;
  // How much of its displacement each skin point takes, in [0, 1] (#P, skin_character order); null =
  // all of it (within the driver's own reach).
  std::shared_ptr<const std::vector<float>> mask;
  std::string mask_source;  // how the mask was made ("joints spine,chest"; "" = none or painted)
  // Control point offsets keyed against joint angles (core/cage/keyposes.h: a key's "vertices" are
  // control points, global index grid by grid), added to the sculpt at each pose.
  std::vector<KeyposeSet> keyposes;
  // Its own binding parameters (local, epsilon, K, scale, distances; the variant is always basic); null =
  // the document cage's, as projects before this field had it.
  std::optional<BindParams> params;
  // How its control points follow the skeleton, like a cage's vertices (rigid, smooth or skin_weights;
  // overrides name control points, global index grid by grid); null = each rigidly to its closest limb,
  // as projects before this field had it.
  std::optional<AttachmentSettings> attachment;
  bool hidden = false;  // its control net not drawn in the editor (a view setting, saved with the project)
  // Contributing-set edits whose element ids are its samples (core/deform/patch_binding.h); canonical.
  std::vector<SetEdit> set_edits;
  // Its binding cached beside the project (P.cagewrap.D<i + 1>.cwb; core/document/binding_cache.h), when the
  // document caches bindings; not part of the work (not compared), like Document::binding_cache.
  BindingCacheRecord binding_cache;
  bool operator==(const DriverPlacement& o) const {
    return name == o.name && hidden == o.hidden && set_edits == o.set_edits && after == o.after && (mask == o.mask || (mask && o.mask && *mask == *o.mask)) && mask_source == o.mask_source &&
           keyposes == o.keyposes && params == o.params && attachment == o.attachment;
  }
};
bool parse_stack_mode(std::string_view name, StackMode& out);

// A parametric driver beyond the document's first (issue 21: a project holds any number): its surface
// and everything the first one's DriverPlacement holds. The drivers' displacements do not depend on one
// another or on the skin they are added to, so their order among themselves does not change the skin:
// the editor edits the first (Document::patch_driver) and makes another one first to edit it
// (with_first_driver).
struct DriverDeformer {
  std::shared_ptr<const PatchDriver> driver;  // never null in a document
  DriverPlacement place;
  bool operator==(const DriverDeformer& o) const {
    return (driver == o.driver || (driver && o.driver && *driver == *o.driver)) && place == o.place;
  }
};

struct Document {
  std::shared_ptr<const Character> character;  // never null in a document made by the functions here
  std::string character_path;  // as given (command line, file dialog) or resolved from the project file
  std::string character_hash;  // "fnv1a64:<hex>" of the character file's bytes (core/base/file_hash.h)
  // An FBX, Collada, ... character read in the file's own units and up axis (--keep-units) rather than brought to
  // metres, Y up (CharacterLoadOptions::keep_units); saved in the project, so it opens the same way.
  bool character_keep_units = false;
  // The character file's bytes when the project embeds the character (saved in the project file,
  // which then needs no other file to open; core/project_storage.h); null = the project names
  // character_path. character_path then tells where the file came from.
  std::shared_ptr<const std::string> embedded_character;
  std::shared_ptr<const Cage> cage;  // the rest cage R; null = no cage yet; replaced on edit
  BindParams params;
  std::vector<SetEdit> set_edits;
  // #Vc offsets of the driver cage D from the posed rest cage, each in the bind space of the joint
  // its vertex follows (so a sculpted bulge travels with the limb); empty = none.
  std::vector<glm::vec3> cage_offsets;
  // How the cage follows the skeleton: rigid or smooth, and per-vertex joint overrides
  // (core/cage/cage_attachment.h).
  AttachmentSettings attachment;
  // Cage vertex offsets keyed against joint angles (core/cage/keyposes.h), added to cage_offsets at
  // each pose before the cage is posed (core/rig/rig.h).
  std::vector<KeyposeSet> keyposes;
  // Secondary motion of the cage (core/cage/cage_sim.h): on or off, parameters, per-vertex weights
  // (#Vc or empty) and colliders; applied per clip by core/rig/clip_sim.h.
  SimSettings sim;
  // The parametric driver (core/deform/patch_surface.h, docs/parametric-drivers.md); null = none. Replaced,
  // never mutated, like the cage.
  std::shared_ptr<const PatchDriver> patch_driver;
  // Its place in the deformer stack, mask and keyposes (kept when the driver is replaced; ignored
  // without one).
  DriverPlacement driver_place;
  // More parametric drivers, each a deformer of the stack like the first (empty without a first one).
  std::vector<DriverDeformer> more_drivers;
  // More deformers of the skin (issue 21): each a cage of its own, combined with the document's cage
  // as `stack` says; empty = the document's cage alone.
  std::vector<DeformerLayer> layers;
  DeformerStack stack;
  // A JSON object (text) of what the project file held that this build does not understand
  // ("extensions" and unknown top-level fields), written back unchanged on save. "" = nothing.
  std::string preserved_fields;
  std::string project_path;  // the .cagewrap file it was loaded from or last saved to; "" = never saved
  // Whether saving the project also writes its binding beside it, so that opening it needs no bind
  // (core/document/binding_cache.h); a project property, saved.
  bool cache_binding = false;
  // The cache the project file recorded when it was loaded (not part of the work: where a
  // by-product lies, like project_path); empty when none.
  BindingCacheRecord binding_cache;
  // A stamp from a process-wide counter, fresh for every content change made through the helpers
  // below: two documents with the same revision have the same content (a renderer can key GPU
  // copies on it; History's dirty flag compares it). Code that edits fields directly must set
  // `revision = next_revision()`.
  uint64_t revision = 0;

  bool has_cage() const { return cage != nullptr; }
  // #V x 3 rest cage positions (empty without a cage).
  std::span<const glm::vec3> cage_positions() const;
};

uint64_t next_revision();

// A new document: the character (glTF, through load_character) and, unless `cage_path` is empty,
// a cage (OBJ/PLY/OFF/STL through load_mesh + make_cage). Default binding parameters, no edits.
// Errors name the file.
Result<Document> document_from_files(const std::string& character_path, const std::string& cage_path,
                                     const CharacterLoadOptions& load = {});

// Copy-on-write edits: each returns a new document with a fresh revision and leaves `doc` alone.
// Same topology, new rest positions (#V x 3; must have exactly cage->num_vertices() entries and
// the document must have a cage: checked, aborts otherwise).
Document with_cage_positions(const Document& doc, std::span<const glm::vec3> positions);
// A different cage (new topology), or none (nullptr). When the vertex count changes, the per-vertex
// data (cage offsets, attachment overrides, keyed vertex offsets) is dropped: it named the old
// cage's vertices. (A topology edit that knows where vertices went should carry it instead:
// overrides_per_vertex / with_overrides_per_vertex and dense_offsets / make_key give it per vertex.)
Document with_cage(const Document& doc, std::shared_ptr<const Cage> cage);
Document with_cage_offsets(const Document& doc, std::vector<glm::vec3> offsets);
Document with_params(const Document& doc, const BindParams& params);
Document with_set_edits(const Document& doc, std::vector<SetEdit> edits);
Document with_attachment(const Document& doc, AttachmentSettings attachment);
Document with_keyposes(const Document& doc, std::vector<KeyposeSet> keyposes);
Document with_sim(const Document& doc, SimSettings sim);
Document with_patch_driver(const Document& doc, std::shared_ptr<const PatchDriver> driver);
Document with_driver_place(const Document& doc, DriverPlacement place);
// Where the driver sits among the layers: driver_place.after clamped to [0, layers.size()].
size_t driver_position(const Document& doc);
size_t driver_position(const Document& doc, const DriverPlacement& place);
// The parameters the parametric driver binds with: its own, or the document cage's.
const BindParams& driver_params(const Document& doc);
const BindParams& driver_params(const Document& doc, const DriverPlacement& place);
// Whether the document's parametric driver moves the skin: it has one, drive_skin is on and no
// deformer is soloed.
bool driver_moves_skin(const Document& doc);
// The parametric drivers: 0 is the first (patch_driver, driver_place), k the more_drivers[k - 1].
// None without a first one.
inline size_t driver_count(const Document& doc) { return doc.patch_driver ? 1 + doc.more_drivers.size() : 0; }
struct DriverRef {
  const PatchDriver* driver = nullptr;
  const DriverPlacement* place = nullptr;
};
// i < driver_count(doc): checked.
DriverRef driver_at(const Document& doc, size_t i);
// Its name: the placement's, or "driver" (the first) / "driver <i + 1>".
std::string driver_name(const Document& doc, size_t i);
// Whether driver i moves the skin: drive_skin on and no deformer soloed.
bool driver_moves_skin(const Document& doc, size_t i);
// The drivers beyond the first (each with a driver: checked; only with a first one: checked).
Document with_more_drivers(const Document& doc, std::vector<DriverDeformer> drivers);
// Driver i made the first (swapped with it), which the editor and `deformer set --driver` edit: the skin
// does not change. i < driver_count(doc): checked.
Document with_first_driver(const Document& doc, size_t i);
// Driver i's placement replaced (its name, place, mask, keyposes, binding). i < driver_count(doc): checked.
Document with_driver_place(const Document& doc, size_t i, DriverPlacement place);
// Driver i replaced in place (a surface, and its placement). i < driver_count(doc), driver not null: checked.
Document with_driver(const Document& doc, size_t i, std::shared_ptr<const PatchDriver> driver, DriverPlacement place);
// The first driver removed: the next one (if any) becomes the first.
Document without_first_driver(const Document& doc);
// The character file moved (or was replaced): new path, hash and data.
Document with_character(const Document& doc, std::shared_ptr<const Character> character, std::string path,
                        std::string hash);
// The character embedded (its file's bytes, whose hash must be character_hash: checked) or not (null).
Document with_embedded_character(const Document& doc, std::shared_ptr<const std::string> bytes);
Document with_cache_binding(const Document& doc, bool cache);
Document with_layers(const Document& doc, std::vector<DeformerLayer> layers);
Document with_stack(const Document& doc, DeformerStack stack);
// The document as layer `i` sees it: its cage, parameters, set edits, offsets, attachment, keyposes
// and simulation in the document's own fields, no layers and no parametric driver (what a Rig is made
// for, and what `cagewrap bind` and the binding cache take). i < doc.layers.size(): checked.
Document layer_document(const Document& doc, size_t i);
// The deformers: 0 is the document's own cage, k the layer k - 1.
inline size_t deformer_count(const Document& doc) { return 1 + doc.layers.size(); }
// The parametric driver stack.solo_driver names (driver_at's number), when there is one.
std::optional<size_t> soloed_driver(const Document& doc);
// The document with driver i soloed (its name baked into its placement, the cages' solo cleared), or no
// driver soloed (nullopt). i < driver_count(doc): checked.
Document with_driver_solo(const Document& doc, std::optional<size_t> i);
// Whether deformer `d` is left out of the stack: muted, or another one (or a driver) is soloed.
bool deformer_muted(const Document& doc, size_t d);
// How many deformers move the skin (those deformer_muted leaves in).
size_t moving_deformers(const Document& doc);
// How many parametric drivers move the skin (driver_moves_skin).
size_t moving_drivers(const Document& doc);
bool deformer_hidden(const Document& doc, size_t d);
// "cage" for 0, else the layer's name.
std::string deformer_name(const Document& doc, size_t d);
// The document as deformer `d` sees it: 0 = the document's cage alone (no layers, no parametric
// driver), else layer_document(doc, d - 1). d < deformer_count(doc): checked.
Document deformer_document(const Document& doc, size_t d);
// Whether two layers are the same work (cage bit for bit, parameters, edits, offsets, attachment,
// keyposes, simulation, mask, name, mute).
bool same_layer(const DeformerLayer& a, const DeformerLayer& b);

// True when the work is the same: character hash and whether it is embedded, cage (topology, and
// positions bit for bit), cage offsets, parameters, set edits, attachment settings, keyposes,
// whether the binding is cached, and preserved fields. Paths, the binding cache record and
// revisions are not compared.
bool same_content(const Document& a, const Document& b);
bool same_params(const BindParams& a, const BindParams& b);
// True when the driver cage moves the same at every pose: same character hash, cage, cage offsets,
// attachment settings, keyposes and simulation settings (what a cached simulation depends on).
bool same_cage_motion(const Document& a, const Document& b);
bool same_set_edits(std::span<const SetEdit> a, std::span<const SetEdit> b);

// Estimated heap bytes, for the undo memory cap (History counts shared data once).
size_t estimated_bytes(const Character& character);
size_t estimated_bytes(const Cage& cage);
// What a snapshot owns by value: set edits, cage offsets, attachment overrides, keyposes, the
// parametric driver's control points, paths,
// preserved fields (not the shared data: character, cage, embedded character bytes).
size_t estimated_own_bytes(const Document& doc);

}  // namespace cagewrap
