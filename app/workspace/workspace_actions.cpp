// The workspace's own actions: the document, the selection, moves, posing and the camera. Each is
// what a menu item, a shortcut or a panel runs, and a script line (docs/editor-actions.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <glm/gtc/quaternion.hpp>

#include "app/workspace/workspace.h"

namespace cagewrap::app {
namespace {

// "cage vertices" -> "cage_vertices": the script spelling of a mode.
std::string script_word(const char* name) {
  std::string s = name;
  std::replace(s.begin(), s.end(), ' ', '_');
  return s;
}

}  // namespace

void Workspace::add_actions() {
  auto add = [this](std::string name, std::string usage, std::string help, std::function<void(std::istringstream&)> run) {
    actions.add({std::move(name), std::move(usage), std::move(help), true, 0, std::move(run)});
  };
  // a file's name is the rest of the line (names may hold spaces)
  auto path_arg = [](std::istringstream& in) {
    std::string path;
    std::getline(in >> std::ws, path);
    path.erase(path.find_last_not_of(" \t\r") + 1);
    return path;
  };

  // ---- selection
  add("mode", "cage_vertices|cage_faces|skin_vertices|joints", "What clicks select and the Select menu acts on (F5..F8).",
      [this](std::istringstream& in) {
        std::string m;
        in >> m;
        for (int k = 0; k < kSelectModes; ++k)
          if (script_word(select_mode_name(static_cast<SelectMode>(k))) == m) {
            view.mode = static_cast<SelectMode>(k);
            return;
          }
        fail("unknown mode '" + m + "'");
      });
  add("select", "all|none|invert|grow|shrink|mirror", "The Select menu, on the active mode's set.", [this](std::istringstream& in) {
    std::string op;
    in >> op;
    for (int k = 0; k < kSelectOps; ++k)
      if (op == select_op_name(static_cast<SelectOp>(k))) {
        edit_selection(static_cast<SelectOp>(k));
        return;
      }
    fail("unknown selection operation '" + op + "'");
  });
  auto select_one = [this](IndexSet Selection::*set) {
    return [this, set](std::istringstream& in) {
      uint32_t i = 0;
      std::string how;
      if (!(in >> i)) return fail("give an index");
      in >> how;
      uint32_t idx[1] = {i};
      if (how == "add") (view.selection.*set).add(idx);
      else (view.selection.*set).set(idx);
    };
  };
  add("select_cage_vertex", "I [add]", "Selects cage vertex I (adds it with `add`).", select_one(&Selection::cage_vertices));
  add("select_cage_face", "I [add]", "Selects cage face I (adds it with `add`).", select_one(&Selection::cage_faces));
  add("select_skin_vertex", "I [add]", "Selects skin vertex I (adds it with `add`).", select_one(&Selection::skin_vertices));
  add("select_joint", "NODE [add]", "Selects the joint of skeleton node NODE (adds it with `add`).", select_one(&Selection::joints));
  add("select_cage_vertices_all", "", "Selects every cage vertex.", [this](std::istringstream&) {
    if (scene_->doc().cage) view.selection.cage_vertices = select_all(scene_->doc().cage->num_vertices());
  });
  add("select_set_faces", "", "Selects the cage faces whose elements drive the selected skin vertices.", [this](std::istringstream&) {
    std::vector<uint32_t> faces;
    if (scene_->binding && scene_->doc().cage && scene_->binding->has_sets())
      for (uint32_t p : view.selection.skin_vertices)
        if (p < scene_->binding->num_points)
          for (uint32_t e : scene_->binding->sets().of(p)) faces.push_back(scene_->doc().cage->element_face[e]);
    view.selection.cage_faces = IndexSet(std::move(faces));
  });
  add("log_set", "I", "Logs the cage elements that drive skin vertex I now.", [this](std::istringstream& in) {
    uint32_t p = 0;
    in >> p;
    std::string text = "set of skin vertex " + std::to_string(p) + ":";
    if (scene_->binding && p < scene_->binding->num_points && scene_->binding->has_sets())
      for (uint32_t e : scene_->binding->sets().of(p)) (text += ' ') += std::to_string(e);
    else text += " (not bound)";
    log(text);
  });

  // ---- moving the cage
  add("soft", "on|off [RADIUS] [smooth|linear|sharp|constant] [volume|surface]", "Soft selection of moves.",
      [this](std::istringstream& in) {
        std::string on, word;
        in >> on;
        view.soft.enabled = on == "on";
        double r;
        if (in >> r) view.soft.radius = r;
        in.clear();
        while (in >> word) {
          for (int k = 0; k < 4; ++k)
            if (word == falloff_name(static_cast<Falloff>(k))) view.soft.falloff = static_cast<Falloff>(k);
          if (word == "surface") view.soft.distance = FalloffDistance::kSurface;
          if (word == "volume") view.soft.distance = FalloffDistance::kVolume;
        }
      });
  add("mirror", "on|off", "X-mirror of moves.", [this](std::istringstream& in) {
    std::string on;
    in >> on;
    view.mirror.enabled = on == "on";
  });
  add("move_target", "rest|pose", "Whether moves sculpt the pose (offsets) or edit the rest cage.", [this](std::istringstream& in) {
    std::string t;
    in >> t;
    if (t != "rest" && t != "pose") return fail("move_target rest|pose");
    view.move_rest = t == "rest";
  });
  add("move", "DX DY DZ", "Moves the selected cage vertices (or faces' corners) by a world displacement: one undo step.",
      [this](std::istringstream& in) {
        glm::dvec3 d(0.0);
        if (!(in >> d.x >> d.y >> d.z)) return fail("move DX DY DZ");
        if (begin_move()) {
          update_move(d);
          end_move();
        }
      });

  // ---- the document
  add("undo", "", "Undoes the last step (Ctrl+Z).", [this](std::istringstream&) { undo(); });
  add("redo", "", "Redoes the step undone (Ctrl+Shift+Z).", [this](std::istringstream&) { redo(); });
  add("bind_param", "variant|local|epsilon|max_elements|scale|max_distance|separation_steps VALUE",
      "Sets a binding parameter in the panel (Rebind applies it).", [this](std::istringstream& in) {
        std::string name, value;
        in >> name >> value;
        const std::string what = "bind_param " + name + ": ";
        BindParams p = scene_->params;
        char* end = nullptr;
        const double v = std::strtod(value.c_str(), &end);
        if (name == "variant") {
          if (!parse_variant(value, p.variant)) return fail(what + "unknown variant '" + value + "'");
        } else if (value.empty() || *end != '\0' || !(v >= 0.0) || v > 1e9) {
          return fail(what + "'" + value + "' is not a non-negative number");
        } else if (name == "local") p.local = v;
        else if (name == "epsilon") p.epsilon = v;
        else if (name == "max_elements") p.max_elements = static_cast<uint32_t>(v);
        else if (name == "scale") p.scale = v;
        else if (name == "max_distance") p.max_distance = v;
        else if (name == "separation_steps") p.separation_steps = static_cast<uint32_t>(v);
        else return fail(what + "unknown parameter");
        if (auto st = validate(p); !st) return fail(what + st.error().message);
        scene_->params = p;
      });
  add("rebind", "", "Binds the skin again with the panel's parameters (one undo step when they changed).",
      [this](std::istringstream&) { scene_->rebind(); });
  add("bind_param_drag", "", "A binding slider is being dragged: the skin binds live with the panel's parameters "
      "(skins up to 200,000 points; else Rebind applies them).",
      [this](std::istringstream&) {
        if (!scene_->live_params_possible())
          return fail("bind_param_drag: live binding is for skins up to " + std::to_string(Scene::kLiveBindPoints) +
                      " points (this one has " + std::to_string(scene_->skin_rest.size()) + "); use rebind");
        scene_->drag_params();
      });
  add("bind_param_release", "", "The binding slider is released: its parameters become the document's (one undo step).",
      [this](std::istringstream&) { scene_->commit_params(); });

  // ---- time and pose (view state)
  add("clip", "NAME|rest", "Shows the clip NAME (the rest of the line) from its start, paused, or the bind pose.",
      [this](std::istringstream& in) {
        std::string name;
        std::getline(in >> std::ws, name);
        name.erase(name.find_last_not_of(" \t\r") + 1);
        if (!select_clip(name)) fail("no clip '" + name + "'");
      });
  add("play", "", "Plays the clip.", [this](std::istringstream&) { view.playback.player.play(); });
  add("pause", "", "Pauses the clip.", [this](std::istringstream&) { view.playback.player.pause(); });
  add("loop", "on|off", "Whether the clip loops (else it stops at its end).", [this](std::istringstream& in) {
    std::string v;
    in >> v;
    if (v != "on" && v != "off") return fail("loop on|off");
    view.playback.player.set_loop(v == "on");
  });
  add("time", "SECONDS", "Moves the clip to a time.", [this](std::istringstream& in) {
    double t = 0.0;
    if (!(in >> t)) return fail("time SECONDS");
    view.playback.player.scrub(t);
  });
  add("pose", "NODE X Y Z", "Rotates a joint on top of the clip (degrees, its local axes; never undone).",
      [this](std::istringstream& in) {
        uint32_t node = 0;
        glm::vec3 deg(0.f);
        if (!(in >> node >> deg.x >> deg.y >> deg.z)) return fail("pose NODE X Y Z");
        set_pose_override(node, glm::quat(glm::radians(deg)));
      });
  add("reset_pose", "", "Drops every joint rotation made on top of the clip.", [this](std::istringstream&) { view.playback.pose_override.clear(); });
  auto compare = [this](std::istringstream& in) {
    std::string v;
    in >> v;
    view.playback.show_file_skinning = v != "off";
  };
  add("file_skinning", "on|off", "Shows the file's own linear blend skinning instead of the cage's (L).", compare);
  add("compare", "on|off", "The same as file_skinning.", compare);

  // ---- the rig (the Rig window runs the same: app/workspace/workspace_rig.cpp)
  add("attach", "rigid|smooth [WIDTH]|skin_weights|fitted|joint|auto",
      "How cage vertices follow the skeleton; `joint`: the selected vertices to the selected joint; `auto`: back to the mode's.",
      [this](std::istringstream& in) {
        std::string what;
        in >> what;
        AttachmentMode mode;
        if (parse_attachment_mode(what, mode)) {
          double width = scene_->doc().attachment.smooth_width;
          in >> width;
          set_attachment_mode(mode, width);
        } else if (what == "joint" || what == "auto") {
          assign_cage_vertices(what == "auto");
        } else {
          fail("attach rigid|smooth [WIDTH]|skin_weights|fitted|joint|auto (got '" + what + "')");
        }
      });
  add("keyset", "x|y|z", "A keypose set driven by the selected joint's rotation about that axis; it becomes the active set.",
      [this](std::istringstream& in) {
        std::string axis;
        in >> axis;
        if (axis != "x" && axis != "y" && axis != "z") return fail("keyset x|y|z");
        add_keypose_set(axis == "y" ? 1 : axis == "z" ? 2 : 0);
      });
  add("keyset_active", "NAME", "Makes the keypose set NAME the one Key, remove_key and mirror_keyset act on.",
      [this](std::istringstream& in) {
        std::string name;
        std::getline(in >> std::ws, name);
        const auto& sets = scene_->doc().keyposes;
        for (size_t i = 0; i < sets.size(); ++i)
          if (sets[i].name == name) {
            view.keypose_set = i;
            return;
          }
        fail("no keypose set '" + name + "'");
      });
  add("key", "", "Keys what was sculpted (the cage's pose offsets) in the active set at its drivers' current angles.",
      [this](std::istringstream&) { key_sculpt(); });
  add("remove_key", "K", "Deletes key K (0 = the first, by driver value) of the active keypose set.", [this](std::istringstream& in) {
    size_t k = 0;
    if (!(in >> k)) return fail("remove_key K");
    remove_key(k);
  });
  add("mirror_keyset", "", "Mirrors the active keypose set to the other side.", [this](std::istringstream&) { mirror_keypose_set(); });

  // ---- the cage (the Cage menu runs the same: app/workspace/workspace_cage.cpp)
  add("import_cage", "PATH", "Imports a cage file (OBJ, PLY, OFF, STL, glTF) as one undo step.", [this, path_arg](std::istringstream& in) {
    const std::string path = path_arg(in);
    if (path.empty()) return fail("import_cage PATH");
    import_cage(path);
  });
  add("auto_cage", "[FACES]", "Builds an automatic cage (FACES triangles, default 2000) in the background.", [this](std::istringstream& in) {
    AutoCageParams params;
    uint32_t faces = 0;
    if (in >> faces) params.target_faces = faces;
    start_auto_cage(params);
  });
  add("auto_cage_cancel", "", "Cancels the automatic cage being built.", [this](std::istringstream&) { cancel_auto_cage(); });
  add("cage_op", "merge|weld D|flip|flip_all|linear [N]|loop [N]|refine|triangulate",
      "A Cage menu operation on the selection (merge: the selected vertices; flip, refine: the selected faces).",
      [this](std::istringstream& in) {
        std::string op;
        double arg = 0.0;
        in >> op >> arg;
        cage_operation(op, arg);
      });

  // ---- contributing sets (the Sets window runs the same: app/workspace/workspace_sets.cpp)
  add("set_edit", "remove|add|only|reset [mirror]", "A set edit on the selected skin vertices with the selected faces.",
      [this](std::istringstream& in) {
        std::string m, mirror;
        in >> m >> mirror;
        SetEditMode mode;
        if (!parse_set_edit_mode(m, mode)) return fail("unknown set edit mode '" + m + "' (remove, add, only, reset)");
        view.sets.mode = mode;
        view.sets.mirror = mirror == "mirror";
        apply_set_edit(view.selection.skin_vertices);
      });
  add("select_limb_faces", "", "Selects the cage faces following the selected joints.",
      [this](std::istringstream&) { view.selection.cage_faces = limb_faces(view.selection.joints); });
  // a skin vertex's first triangle, for the brushes' one-dab strokes (said why when there is none)
  const auto triangle_of = [this](uint32_t i) -> std::optional<uint32_t> {
    if (i >= scene_->skin_posed().size()) {
      fail("no skin vertex " + std::to_string(i));
      return std::nullopt;
    }
    const auto& fv = scene_->skin_topology.face_vertices;
    const auto at = std::find(fv.begin(), fv.end(), i);
    if (at == fv.end()) {
      fail("skin vertex " + std::to_string(i) + " is on no triangle");
      return std::nullopt;
    }
    return static_cast<uint32_t>((at - fv.begin()) / 3);
  };
  add("paint_at_skin_vertex", "I [RADIUS]", "One brush stroke of one dab at skin vertex I (RADIUS in scene units).",
      [this, triangle_of](std::istringstream& in) {
        uint32_t i = 0;
        double r = 0.0;
        if (!(in >> i)) return fail("paint_at_skin_vertex I [RADIUS]");
        if (in >> r && r > 0) view.sets.brush_radius = r;
        const auto t = triangle_of(i);
        if (!t) return;
        begin_set_stroke();
        set_stroke_dab(*t, glm::dvec3(scene_->skin_posed()[i]));
        end_set_stroke();
      });

  // ---- the mask brush (app/workspace/workspace_mask.cpp)
  add("mask_paint", "on|off [driver I]", "The mask brush on (clicks on the skin paint the active layer's mask, or parametric driver I's) or off.",
      [this](std::istringstream& in) {
        std::string on, what;
        long i = -1;
        in >> on >> what;
        if ((on != "on" && on != "off") || (!what.empty() && (what != "driver" || !(in >> i) || i < 0)))
          return fail("mask_paint on|off [driver I]");
        view.mask.driver = what == "driver" ? static_cast<int>(i) : -1;
        view.mask.painting = on == "on" && mask_target(true).has_value();
      });
  add("mask_brush", "VALUE STRENGTH [RADIUS]", "The mask brush: the weight it paints toward (0..1), how far per dab (0..1], its radius (scene units).",
      [this](std::istringstream& in) {
        float value = -1.0f, strength = -1.0f;
        double radius = 0.0;
        if (!(in >> value >> strength) || value < 0.0f || value > 1.0f || strength <= 0.0f || strength > 1.0f)
          return fail("mask_brush VALUE STRENGTH [RADIUS]: VALUE 0..1, STRENGTH in (0, 1]");
        view.mask.value = value;
        view.mask.strength = strength;
        if (in >> radius && radius > 0.0) view.mask.radius = radius;
      });
  add("mask_paint_at_skin_vertex", "I", "One mask-brush stroke of one dab at skin vertex I (one undo step).",
      [this, triangle_of](std::istringstream& in) {
        uint32_t i = 0;
        if (!(in >> i)) return fail("mask_paint_at_skin_vertex I");
        const auto t = triangle_of(i);
        if (!t) return;
        begin_mask_stroke();
        mask_stroke_dab(*t, glm::dvec3(scene_->skin_posed()[i]));
        end_mask_stroke();
      });
  add("mask_fill", "VALUE", "Every weight of the painted mask to VALUE (0..1): one undo step.", [this](std::istringstream& in) {
    float v = -1.0f;
    if (!(in >> v)) return fail("mask_fill VALUE");
    fill_mask(v);
  });

  // ---- the parametric driver (the Parametric driver window runs the same: app/workspace/workspace_patch.cpp)
  // those that start or stop a bind give the frame loop a frame, so that a script waits for the bind
  auto add_bind = [this](std::string name, std::string usage, std::string help, std::function<void(std::istringstream&)> run) {
    actions.add({std::move(name), std::move(usage), std::move(help), true, 1, std::move(run)});
  };
  add_bind("patch_import", "PATH", "Imports a parametric driver (.cwpatch or glTF); it enters the document once bound.",
      [this, path_arg](std::istringstream& in) {
        const std::string path = path_arg(in);
        if (path.empty()) return fail("patch_import PATH");
        import_patch_driver(path);
      });
  add("patch_export", "PATH", "Writes the parametric driver's posed control points (.cwpatch or glTF).",
      [this, path_arg](std::istringstream& in) {
        const std::string path = path_arg(in);
        if (path.empty()) return fail("patch_export PATH");
        export_patch_driver(path);
      });
  add_bind("patch_fit", "", "Fits a parametric driver to the selected cage faces (a rectangle of quads).",
      [this](std::istringstream&) { fit_patch_driver(); });
  add_bind("patch_density", "N [nowait]", "The driver's sampling density (1..1024), bound in the background (a script waits unless nowait).",
      [this](std::istringstream& in) {
        uint32_t d = 0;
        std::string wait;
        if (!(in >> d)) return fail("patch_density N [nowait]");
        in >> wait;
        set_patch_density(d, wait == "nowait");
      });
  add("patch_select", "I", "Selects control point I of the driver (-1: none).", [this](std::istringstream& in) {
    int i = -1;
    if (!(in >> i)) return fail("patch_select I");
    select_patch_point(i);
  });
  add("patch_move", "DX DY DZ", "Moves the selected control point: one undo step.", [this](std::istringstream& in) {
    glm::dvec3 d(0.0);
    if (!(in >> d.x >> d.y >> d.z)) return fail("patch_move DX DY DZ");
    move_patch_point(d);
  });
  add("patch_reset", "", "Puts the driver's control points back at rest.", [this](std::istringstream&) { reset_patch_driver(); });
  add("patch_drive", "on|off", "Whether the driver drives the skin (instead of the cage).", [this](std::istringstream& in) {
    std::string on;
    in >> on;
    if (on != "on" && on != "off") return fail("patch_drive on|off");
    set_patch_drive(on == "on");
  });
  add_bind("patch_bind", "", "Binds the document's driver to the skin again.", [this](std::istringstream&) { bind_patch_driver(); });
  add_bind("patch_cancel", "", "Cancels the driver's bind under way (the driver is unchanged).",
      [this](std::istringstream&) { cancel_patch_bind(); });
  add("driver_add", "PATH", "Adds a parametric driver (.cwpatch or glTF): the first, or one more; each binds in the background.",
      [this, path_arg](std::istringstream& in) {
        const std::string path = path_arg(in);
        if (path.empty()) return fail("driver_add PATH");
        add_driver(path);
      });
  const auto driver_index = [this](std::istringstream& in, const char* usage) -> std::optional<size_t> {
    long i = -1;
    if (!(in >> i) || i < 0) {
      fail(usage);
      return std::nullopt;
    }
    return static_cast<size_t>(i);
  };
  add("driver_edit", "I", "Makes parametric driver I (0 = the first) the one the driver window and the patch_* actions edit (the skin does not change).",
      [this, driver_index](std::istringstream& in) {
        if (auto i = driver_index(in, "driver_edit I")) make_driver_first(*i);
      });
  // "I on|off" for driver I, then `set(i, on)`
  const auto driver_switch = [this, driver_index](std::string usage, bool (Workspace::*set)(size_t, bool)) {
    return [this, driver_index, usage, set](std::istringstream& in) {
      auto i = driver_index(in, usage.c_str());
      std::string on;
      in >> on;
      if (!i) return;
      if (on != "on" && on != "off") return fail(usage);
      (this->*set)(*i, on == "on");
    };
  };
  add("driver_mute", "I on|off", "Mutes (on) or unmutes (off) parametric driver I: left out of the stack, kept in the project.",
      driver_switch("driver_mute I on|off", &Workspace::set_driver_muted));
  add("driver_after", "I K|last", "Where parametric driver I sits in the stack: after K layers (0: right after the document's cage), or after them all.",
      [this, driver_index](std::istringstream& in) {
        auto i = driver_index(in, "driver_after I K|last");
        std::string k;
        in >> k;
        if (!i) return;
        char* end = nullptr;
        const long v = std::strtol(k.c_str(), &end, 10);
        if (k == "last") set_driver_after(-1, *i);
        else if (k.empty() || *end || v < 0) fail("driver_after I K|last");
        else set_driver_after(static_cast<int>(v), *i);
      });
  add("driver_hide", "I on|off", "Hides (on) or shows (off) parametric driver I's control net (saved with the project).",
      driver_switch("driver_hide I on|off", &Workspace::set_driver_hidden));
  add("driver_solo", "I|off", "Only parametric driver I moves the skin (the cages leave the rest skin), or no driver soloed: one undo step.",
      [this, driver_index](std::istringstream& in) {
        std::string v;
        in >> v;
        if (v == "off") return static_cast<void>(set_driver_solo(std::nullopt));
        std::istringstream again(v);
        if (auto i = driver_index(again, "driver_solo I|off")) set_driver_solo(*i);
      });
  add("driver_remove", "I", "Removes parametric driver I (0 = the first; the next one then becomes the first).",
      [this, driver_index](std::istringstream& in) {
        if (auto i = driver_index(in, "driver_remove I")) remove_driver(*i);
      });
  add("patch_after", "K|last", "Where the driver sits in the stack: after K layers (0: right after the document's cage), or after them all.",
      [this](std::istringstream& in) {
        std::string k;
        in >> k;
        char* end = nullptr;
        const long v = std::strtol(k.c_str(), &end, 10);
        if (k == "last") set_driver_after(-1);
        else if (k.empty() || *end || v < 0) fail("patch_after K|last");
        else set_driver_after(static_cast<int>(v));
      });
  add("patch_mask", "joints a,b,-c | primitives 0,2 | meshes body | none",
      "The skin the driver may move: these joints' region (feathered by the skin weights; -c leaves one out), these primitives or glTF meshes, or all of it.",
      [this](std::istringstream& in) {
        std::string kind, list;
        in >> kind >> list;
        if (kind == "none") set_driver_mask("");
        else if ((kind == "joints" || kind == "primitives" || kind == "meshes") && !list.empty()) set_driver_mask(kind + " " + list);
        else fail("patch_mask joints a,b,-c | primitives 0,2 | meshes body | none");
      });
  add("patch_key", "X|Y|Z", "Keys the driver's sculpt against the selected joint's rotation about its local axis at this pose (the control points go back to rest).",
      [this](std::istringstream& in) {
        std::string a;
        in >> a;
        if (a != "X" && a != "Y" && a != "Z") return fail("patch_key X|Y|Z");
        key_driver_sculpt(a[0] - 'X');
      });
  add("patch_binding", "cage | LOCAL EPSILON K", "The driver's own binding parameters (the rest as the cage's), or the cage's again: one undo step; it binds again.",
      [this](std::istringstream& in) {
        std::string first;
        in >> first;
        if (first == "cage") return static_cast<void>(set_driver_params(std::nullopt));
        double local = 0, epsilon = 0;
        unsigned k = 0;
        std::istringstream rest(first);
        if (!(rest >> local) || !(in >> epsilon >> k)) return fail("patch_binding cage | LOCAL EPSILON K");
        BindParams p = scene_ ? driver_params(scene_->work()) : BindParams{};
        p.local = local;
        p.epsilon = epsilon;
        p.max_elements = k;
        set_driver_params(p);
      });
  add("patch_attach", "closest|rigid|smooth|skin_weights", "How the driver's control points follow the skeleton: each to its closest limb, or like a cage's vertices: one undo step.",
      [this](std::istringstream& in) {
        std::string m;
        in >> m;
        AttachmentMode mode{};
        if (m == "closest") set_driver_attachment(std::nullopt);
        else if (parse_attachment_mode(m, mode) && mode != AttachmentMode::kFitted) set_driver_attachment(mode);
        else fail("patch_attach closest|rigid|smooth|skin_weights");
      });
  add("patch_attach_point", "I JOINT|auto", "Attaches the driver's control point I to JOINT (auto: back to automatic): one undo step.",
      [this](std::istringstream& in) {
        uint32_t i = 0;
        std::string joint;
        if (!(in >> i >> joint)) return fail("patch_attach_point I JOINT|auto");
        std::optional<uint32_t> node;
        if (joint != "auto") {
          const Skeleton& sk = scene_->doc().character->skeleton;
          for (uint32_t n = 0; n < sk.size() && !node; ++n)
            if (sk.node(n).name == joint) node = n;
          if (!node) return fail("patch_attach_point: the skeleton has no node '" + joint + "'");
        }
        assign_driver_points(std::span<const uint32_t>(&i, 1), node);
      });
  add_bind("patch_set_edits", "PATH|none", "The driver's contributing-set edits from a set edits file (per-point edits of its samples), or none: one undo step; it binds again.",
      [this, path_arg](std::istringstream& in) {
        const std::string path = path_arg(in);
        if (path.empty()) return fail("patch_set_edits PATH|none");
        set_driver_set_edits(path == "none" ? std::string() : path);
      });
  // its set edits picked in the view (app/workspace/workspace_driver_sets.cpp)
  add("patch_samples", "on|off", "The driver window's sample tool: clicks pick the driver's samples (its set elements) instead of control points.",
      [this](std::istringstream& in) {
        std::string on;
        in >> on;
        if (on != "on" && on != "off") return fail("patch_samples on|off");
        view.patch.samples = on == "on";
        if (view.patch.samples) view.patch.editing = true;
      });
  add("patch_sample_select", "I[,J...] [add]|none", "Picks the driver's samples I, J, ... (adds them with `add`), or none.",
      [this](std::istringstream& in) {
        std::string list, mode;
        in >> list >> mode;
        if (list == "none") return view.patch.picked.clear();
        std::vector<uint32_t> ids;
        std::istringstream items(list);
        for (std::string item; std::getline(items, item, ',');) {
          char* end = nullptr;
          const unsigned long v = std::strtoul(item.c_str(), &end, 10);
          if (item.empty() || *end || item[0] == '-') return fail("patch_sample_select I[,J...] [add]|none");
          ids.push_back(static_cast<uint32_t>(v));
        }
        const auto& driver = scene_->work().patch_driver;
        const size_t n = driver ? patch_sample_count(driver->rest, driver->density) : 0;
        for (uint32_t v : ids)
          if (v >= n) return fail("no sample " + std::to_string(v) + " (the driver has " + std::to_string(n) + ")");
        if (ids.empty()) return fail("patch_sample_select I[,J...] [add]|none");
        if (mode == "add") view.patch.picked.add(ids);
        else view.patch.picked.set(ids);
      });
  add("patch_select_set_samples", "", "Picks the driver's samples that drive the selected skin vertices.",
      [this](std::istringstream&) { select_driver_set_samples(); });
  add_bind("patch_set_edit", "remove|add|only|reset", "A set edit of the driver: the picked samples on the selected skin vertices; one undo step; it binds again.",
      [this](std::istringstream& in) {
        std::string m;
        in >> m;
        SetEditMode mode;
        if (!parse_set_edit_mode(m, mode)) return fail("unknown set edit mode '" + m + "' (remove, add, only, reset)");
        driver_set_edit(mode);
      });
  add("patch_keyset_remove", "I", "Removes the driver's keypose set I.", [this](std::istringstream& in) {
    size_t i = 0;
    if (!(in >> i)) return fail("patch_keyset_remove I");
    remove_driver_keyset(i);
  });
  add("patch_panel", "", "Edits the parametric driver: clicks pick control points, the move gizmo moves them.",
      [this](std::istringstream&) { view.patch.editing = true; });

  // ---- fidelity to the file's skinning (the Properties window runs the same: app/workspace/workspace_fidelity.cpp)
  add("heatmap", "on|off", "The fidelity heat map on the skin.", [this](std::istringstream& in) {
    std::string v;
    in >> v;
    if (v != "on" && v != "off") return fail("heatmap on|off");
    view.fidelity.heat_map = v == "on";
  });
  add_bind("fidelity_check", "[nowait]", "Checks all clips against the file's skinning in the background (a script waits unless nowait).",
           [this](std::istringstream& in) {
             std::string wait;
             in >> wait;
             start_fidelity_check(wait == "nowait");
           });
  add_bind("fidelity_check_nowait", "", "fidelity_check nowait.", [this](std::istringstream&) { start_fidelity_check(true); });
  add("fidelity_cancel", "", "Cancels the running check.", [this](std::istringstream&) { cancel_fidelity_check(); });
  add("fidelity_frame", "", "Logs this frame's fidelity figures.", [this](std::istringstream&) {
    update_pose();
    measure_fidelity();
    const auto& f = fidelity_.frame;
    if (!f) return log("fidelity, this frame: not measured (no binding, or the file's skinning is shown)");
    char buf[256];
    std::snprintf(buf, sizeof buf, "fidelity, this frame: worst %.4f%% (vertex %u, joint '%s'), RMS %.4f%%, stretch %.3fx",
                  100 * f->worst, f->worst_vertex, joint_name(f->worst_joint).c_str(), 100 * f->rms, f->stretch);
    log(buf);
  });

  // ---- project storage (the File menu runs the same: app/workspace/workspace_project.cpp)
  add("embed", "on|off [PATH]", "Keeps the character file inside the project (on), or writes it out to PATH or where it came from (off).",
      [this, path_arg](std::istringstream& in) {
        std::string on;
        in >> on;
        if (on != "on" && on != "off") return fail("embed on|off [PATH]");
        if (on == "on") embed_character();
        else unembed_character(path_arg(in));
      });
  add("cache_binding", "on|off", "Saves the binding beside the project, so that opening it needs no bind.",
      [this](std::istringstream& in) {
        std::string on;
        in >> on;
        if (on != "on" && on != "off") return fail("cache_binding on|off");
        set_cache_binding(on == "on");
      });

  // ---- the cage simulation (the Simulation window runs the same: app/workspace/workspace_sim.cpp)
  add("sim", "on|off", "The cage simulation of the clips.", [this](std::istringstream& in) {
    std::string what;
    in >> what;
    if (what != "on" && what != "off") return fail("sim on|off");
    set_simulation(what == "on");
  });
  add("sim_weights", "pin|free [MASS STIFFNESS]", "Paints the selected cage vertices pinned or free (the soft selection blends).",
      [this](std::istringstream& in) {
        std::string what;
        float mass = 1.0f, stiffness = 0.3f;
        in >> what >> mass >> stiffness;
        if (what != "pin" && what != "free") return fail("sim_weights pin|free [MASS STIFFNESS]");
        set_sim_weights(what == "pin", mass, stiffness);
      });
  add("sim_param", "gravity|damping|goal_frequency|iterations|substeps|preroll|margin|skeleton|edges VALUE", "A simulation setting.",
      [this](std::istringstream& in) {
        std::string name;
        double value = 0.0;
        if (!(in >> name >> value)) return fail("sim_param NAME VALUE");
        SimParams p = scene_->doc().sim.params;
        if (name == "gravity") p.gravity.y = value;
        else if (name == "damping") p.damping = value;
        else if (name == "goal_frequency") p.goal_frequency = value;
        else if (name == "iterations") p.iterations = static_cast<int>(value);
        else if (name == "substeps") p.substeps = static_cast<int>(value);
        else if (name == "preroll") p.preroll = value;
        else if (name == "margin") p.collision_margin = value;
        else if (name == "skeleton") p.skeleton_colliders = value != 0.0;
        else if (name == "edges") p.edges = value != 0.0;
        else return fail("unknown simulation parameter '" + name + "'");
        set_sim_params(p);
      });
  add("sim_collider", "plane|sphere|capsule AX AY AZ BX BY BZ R", "Adds a collider.", [this](std::istringstream& in) {
    std::string kind;
    Collider c;
    in >> kind >> c.a.x >> c.a.y >> c.a.z >> c.b.x >> c.b.y >> c.b.z >> c.radius;
    if (!parse_collider_kind(kind, c.kind)) return fail("unknown collider kind '" + kind + "' (plane, sphere, capsule)");
    if (!in) return fail("sim_collider KIND AX AY AZ BX BY BZ R");
    add_collider(c);
  });
  add("sim_remove_collider", "I", "Removes collider I.", [this](std::istringstream& in) {
    size_t i = 0;
    if (!(in >> i)) return fail("sim_remove_collider I");
    remove_collider(i);
  });

  // ---- export (the Export window runs the same: app/workspace/workspace_export.cpp; the window's
  // script versions open the window first and hold the script until the export ends)
  auto export_line = [this](std::istringstream& in) {
    auto request = parse_export(in);
    if (!request) return refuse_export(where_ + ": " + request.error().message);
    start_export(*request);
  };
  add("export", "FORMAT MODE|- FPS all|CLIP[,CLIP] PATH", "Exports the rig (glb, obj or json) in the background.", export_line);
  add("export_nowait", "FORMAT MODE|- FPS all|CLIP[,CLIP] PATH", "The same; a script goes on meanwhile.", export_line);
  add("export_correctives", "N|frames|default [MAX_ERROR]",
      "The corrective morph targets of the next glb skin exports: at most N principal components (with MAX_ERROR, the fewest within it, "
      "in the file's units), one per frame, or the mode's default (16 for baked-skin).",
      [this](std::istringstream& in) {
        std::string n;
        double e = 0.0;
        in >> n;
        if (!(in >> e)) e = 0.0;
        char* end = nullptr;
        const long v = std::strtol(n.c_str(), &end, 10);
        const bool number = !n.empty() && !*end && v >= 1 && v <= 4096;
        if ((!number && n != "frames" && n != "default") || !(e >= 0.0) || !std::isfinite(e) || (e > 0.0 && n == "frames"))
          return fail("export_correctives N|frames|default [MAX_ERROR] (N from 1 to 4096; MAX_ERROR >= 0, not with frames)");
        export_correctives.max_targets = n == "frames" ? 0 : n == "default" ? -1 : static_cast<int>(v);
        export_correctives.max_error = e;
      });
  add("export_influences", "4|8", "The fitted joints per vertex of the next baked-skin exports: 4, or 8 (JOINTS_1/WEIGHTS_1 too).",
      [this](std::istringstream& in) {
        int n = 0;
        if (!(in >> n) || (n != 4 && n != 8)) return fail("export_influences 4|8");
        export_correctives.max_influences = n;
      });
  add("export_optimize", "on|off", "Whether the next glb exports are reordered for the GPU (vertex cache and fetch order).",
      [this](std::istringstream& in) { read_on_off(in, "export_optimize", export_correctives.optimize); });
  add("export_quantize", "on|off", "Whether the next glb exports are quantized (KHR_mesh_quantization: 16-bit positions and targets).",
      [this](std::istringstream& in) { read_on_off(in, "export_quantize", export_correctives.quantize); });
  add("export_pose_driven", "on|off [CLIP]",
      "Whether the next baked-skin exports' correctives are driven by joint angles (docs/pose-correctives.md), holding CLIP out of "
      "the fits.",
      [this](std::istringstream& in) {
        std::string on, clip;
        in >> on;
        std::getline(in >> std::ws, clip);
        if ((on != "on" && on != "off") || (on == "off" && !clip.empty())) return fail("export_pose_driven on|off [CLIP]");
        export_correctives.pose_driven = on == "on";
        export_correctives.hold_out = clip;
      });
  add("export_cancel", "", "Cancels the running export.", [this](std::istringstream&) { cancel_export(); });

  // ---- the camera
  add("view", "front|right|top", "A preset view.", [this](std::istringstream& in) {
    std::string v;
    in >> v;
    view.camera.set_preset(v == "right" ? ViewPreset::kRight : v == "top" ? ViewPreset::kTop : ViewPreset::kFront);
  });
  add("camera", "YAW PITCH DISTANCE [TX TY TZ]", "Places the orbit camera (degrees, scene units).", [this](std::istringstream& in) {
    double yaw = 0, pitch = 0, dist = 0;
    in >> yaw >> pitch >> dist;
    view.camera.set_angles(glm::radians(yaw), glm::radians(pitch));
    view.camera.set_distance(dist);
    glm::dvec3 t;
    if (in >> t.x >> t.y >> t.z) view.camera.set_target(t);
  });
}

void Workspace::read_on_off(std::istringstream& in, const char* action, bool& flag) {
  std::string on;
  in >> on;
  if (on != "on" && on != "off") return fail(std::string(action) + " on|off");
  flag = on == "on";
}

}  // namespace cagewrap::app
