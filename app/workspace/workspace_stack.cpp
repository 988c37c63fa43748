// The deformer stack in the editor (issue 21, docs/deformer-stack.md): which deformer the tools act on,
// and the stack's edits (a layer added or removed, muted, hidden, soloed, moved, renamed; the mode),
// each one undo step. The outliner's Deformers list and the deformer_* actions run these.
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "app/workspace/workspace.h"
#include "core/character/skin_mask.h"

namespace cagewrap::app {

bool Workspace::binding_any() const {
  if (!scene_) return false;
  if (scene_->job) return true;
  for (const StackRig& r : scene_->stack_rigs)
    if (r.job) return true;
  for (const DriverRig& r : scene_->driver_rigs)
    if (r.job) return true;
  return false;
}

bool Workspace::check_deformer(size_t d, bool layer_only) {
  if (!scene_) return false;
  const size_t n = deformer_count(scene_->work());
  if (d >= n) {
    fail("no deformer " + std::to_string(d) + " (the deformers are 0 to " + std::to_string(n - 1) + ")");
    return false;
  }
  if (layer_only && d == 0) {
    fail("deformer 0 is the document's own cage: it cannot be removed or moved (replace it with Cage > Import)");
    return false;
  }
  return true;
}

bool Workspace::change_stack(const std::string& label, Document next) {
  cancel_move();
  end_set_stroke();
  end_mask_stroke();
  if (!scene_->apply_work(label, std::move(next))) return false;
  log(label);
  return true;
}

bool Workspace::set_active_deformer(size_t d) {
  if (!check_deformer(d, false)) return false;
  if (d == scene_->active_deformer()) return true;
  cancel_move();
  end_set_stroke();
  end_mask_stroke();
  if (!scene_->set_active_deformer(d)) {
    fail("the active deformer cannot change during a drag");
    return false;
  }
  view.selection = {};  // it named the other cage's vertices and faces
  clip_cage_selection();
  log("editing deformer " + std::to_string(d) + " '" + deformer_name(scene_->work(), d) + "'");
  return true;
}

bool Workspace::add_deformer(const std::string& cage_path, std::string name) {
  if (!scene_) return false;
  auto cage = read_cage(cage_path);
  if (!cage) return false;
  const Document& w = scene_->work();
  if (name.empty()) name = std::filesystem::path(cage_path).stem().string();
  for (size_t d = 0; d < deformer_count(w); ++d)
    if (deformer_name(w, d) == name) {
      fail("there is a deformer named '" + name + "' already: give another name");
      return false;
    }
  DeformerLayer l;
  l.name = name;
  l.cage = std::make_shared<const Cage>(std::move(*cage));
  l.params = w.params;
  l.attachment = w.attachment;
  l.attachment.overrides.clear();  // they named the document cage's vertices
  std::vector<DeformerLayer> layers = w.layers;
  layers.push_back(std::move(l));
  return change_stack("Add deformer " + name, with_layers(w, std::move(layers)));
}

bool Workspace::remove_deformer(size_t d) {
  if (!check_deformer(d, true)) return false;
  const Document& w = scene_->work();
  const std::string name = deformer_name(w, d);
  if (scene_->active_deformer() == d) scene_->set_active_deformer(0);
  std::vector<DeformerLayer> layers = w.layers;
  layers.erase(layers.begin() + static_cast<long>(d - 1));
  Document next = with_layers(w, std::move(layers));
  if (next.stack.solo >= 0) {  // the numbers after it moved down
    DeformerStack st = next.stack;
    if (static_cast<size_t>(st.solo) == d) st.solo = -1;
    else if (static_cast<size_t>(st.solo) > d) --st.solo;
    next = with_stack(next, st);
  }
  if (scene_->active_deformer() > d) scene_->set_active_deformer(0);
  return change_stack("Remove deformer " + name, std::move(next));
}

// A deformer's switch (mute or hide): the stack's for the document's own cage, the layer's for a layer.
bool Workspace::set_deformer_switch(size_t d, bool on, bool DeformerStack::*base, bool DeformerLayer::*layer, const std::string& label) {
  if (!check_deformer(d, false)) return false;
  const Document& w = scene_->work();
  const std::string what = label + " " + deformer_name(w, d);
  if (d == 0) {
    DeformerStack st = w.stack;
    st.*base = on;
    return change_stack(what, with_stack(w, st));
  }
  std::vector<DeformerLayer> layers = w.layers;
  layers[d - 1].*layer = on;
  return change_stack(what, with_layers(w, std::move(layers)));
}

bool Workspace::make_mask(const Document& w, const std::string& source, std::shared_ptr<const std::vector<float>>& mask,
                          std::string& mask_source, const std::string& what) {
  if (source.empty()) {
    mask = nullptr;
    mask_source.clear();
    return true;
  }
  auto m = skin_mask_from_source(*w.character, source);
  if (!m) {
    fail(what + ": mask: " + m.error().message);
    return false;
  }
  mask = std::make_shared<const std::vector<float>>(std::move(m).value());
  mask_source = source;
  return true;
}

bool Workspace::set_deformer_mask(size_t d, const std::string& source) {
  if (!check_deformer(d, true)) return false;
  const Document& w = scene_->work();
  std::vector<DeformerLayer> layers = w.layers;
  DeformerLayer& l = layers[d - 1];
  if (!make_mask(w, source, l.mask, l.mask_source, "deformer '" + l.name + "'")) return false;
  const std::string label = source.empty() ? "Remove the mask of " + l.name : "Mask " + l.name + ": " + source;
  return change_stack(label, with_layers(w, std::move(layers)));
}

bool Workspace::set_deformer_muted(size_t d, bool muted) {
  return set_deformer_switch(d, muted, &DeformerStack::base_muted, &DeformerLayer::muted, muted ? "Mute deformer" : "Unmute deformer");
}

bool Workspace::set_deformer_hidden(size_t d, bool hidden) {
  return set_deformer_switch(d, hidden, &DeformerStack::base_hidden, &DeformerLayer::hidden, hidden ? "Hide deformer" : "Show deformer");
}

bool Workspace::set_deformer_solo(long d) {
  if (d >= 0 && !check_deformer(static_cast<size_t>(d), false)) return false;
  if (!scene_) return false;
  const Document& w = scene_->work();
  DeformerStack st = w.stack;
  st.solo = d < 0 ? -1 : static_cast<int32_t>(d);
  st.solo_driver.clear();
  return change_stack(d < 0 ? std::string("Unsolo deformers") : "Solo deformer " + deformer_name(w, static_cast<size_t>(d)),
                      with_stack(w, st));
}

bool Workspace::move_deformer(size_t d, size_t to) {
  if (!check_deformer(d, true)) return false;
  const Document& w = scene_->work();
  if (to < 1 || to > w.layers.size()) {
    fail("a layer moves to 1 .. " + std::to_string(w.layers.size()) + " (0 is the document's own cage, always first)");
    return false;
  }
  if (to == d) return true;
  const std::string name = deformer_name(w, d);
  std::vector<DeformerLayer> layers = w.layers;
  DeformerLayer moved = std::move(layers[d - 1]);
  layers.erase(layers.begin() + static_cast<long>(d - 1));
  layers.insert(layers.begin() + static_cast<long>(to - 1), std::move(moved));
  // the solo and the active deformer follow their layers
  const auto renumber = [&](size_t k) {
    if (k == d) return to;
    if (d < to && k > d && k <= to) return k - 1;
    if (to < d && k >= to && k < d) return k + 1;
    return k;
  };
  Document next = with_layers(w, std::move(layers));
  if (next.stack.solo > 0) {
    DeformerStack st = next.stack;
    st.solo = static_cast<int32_t>(renumber(static_cast<size_t>(st.solo)));
    next = with_stack(next, st);
  }
  const size_t active = renumber(scene_->active_deformer());
  if (active != scene_->active_deformer()) scene_->set_active_deformer(0);
  if (!change_stack("Move deformer " + name + " to " + std::to_string(to), std::move(next))) return false;
  scene_->set_active_deformer(active);
  return true;
}

bool Workspace::rename_deformer(size_t d, const std::string& name) {
  if (!check_deformer(d, true)) return false;
  const Document& w = scene_->work();
  if (name.empty()) {
    fail("a deformer needs a name");
    return false;
  }
  for (size_t k = 0; k < deformer_count(w); ++k)
    if (k != d && deformer_name(w, k) == name) {
      fail("there is a deformer named '" + name + "' already");
      return false;
    }
  std::vector<DeformerLayer> layers = w.layers;
  const std::string old = layers[d - 1].name;
  layers[d - 1].name = name;
  return change_stack("Rename deformer " + old + " to " + name, with_layers(w, std::move(layers)));
}

bool Workspace::set_stack_mode(StackMode mode, double exponent) {
  if (!scene_) return false;
  if (!(exponent >= 0.0) || !std::isfinite(exponent)) {
    fail("the blend's exponent must be a number >= 0");
    return false;
  }
  DeformerStack st = scene_->work().stack;
  st.mode = mode;
  st.exponent = exponent;
  return change_stack(std::string("Combine deformers: ") + stack_mode_name(mode), with_stack(scene_->work(), st));
}

void Workspace::add_stack_actions() {
  // those that start binds give the frame loop a frame, so that a script waits for them
  auto add = [this](std::string name, std::string usage, std::string help, std::function<void(std::istringstream&)> run) {
    actions.add({std::move(name), std::move(usage), std::move(help), true, 1, std::move(run)});
  };
  auto on_off = [](std::istringstream& in, bool& out) {
    std::string w;
    in >> w;
    if (w != "on" && w != "off") return false;
    out = w == "on";
    return true;
  };
  add("deformer_active", "D", "Edits deformer D (0: the document's cage): selection, gizmo, sets, keyposes and Rebind act on it.",
      [this](std::istringstream& in) {
        size_t d = 0;
        if (!(in >> d)) return fail("deformer_active D");
        set_active_deformer(d);
      });
  add("deformer_add", "PATH", "Adds the cage at PATH as a layer at the end of the stack, bound in the background: one undo step.",
      [this](std::istringstream& in) {
        std::string path;
        std::getline(in >> std::ws, path);
        path.erase(path.find_last_not_of(" \t\r") + 1);
        if (path.empty()) return fail("deformer_add PATH");
        add_deformer(path);
      });
  add("deformer_remove", "D", "Removes layer D (1 = the first): one undo step.", [this](std::istringstream& in) {
    size_t d = 0;
    if (!(in >> d)) return fail("deformer_remove D");
    remove_deformer(d);
  });
  add("deformer_mute", "D on|off", "Leaves deformer D out of the stack (on) or puts it back: one undo step.",
      [this, on_off](std::istringstream& in) {
        size_t d = 0;
        bool on = false;
        if (!(in >> d) || !on_off(in, on)) return fail("deformer_mute D on|off");
        set_deformer_muted(d, on);
      });
  add("deformer_hide", "D on|off", "Hides deformer D's cage in the view (on) or shows it: one undo step.",
      [this, on_off](std::istringstream& in) {
        size_t d = 0;
        bool on = false;
        if (!(in >> d) || !on_off(in, on)) return fail("deformer_hide D on|off");
        set_deformer_hidden(d, on);
      });
  add("deformer_solo", "D|off", "Only deformer D moves the skin (off: all that are not muted): one undo step.",
      [this](std::istringstream& in) {
        std::string w;
        in >> w;
        if (w == "off") return static_cast<void>(set_deformer_solo(-1));
        char* end = nullptr;
        const long d = std::strtol(w.c_str(), &end, 10);
        if (w.empty() || *end || d < 0) return fail("deformer_solo D|off");
        set_deformer_solo(d);
      });
  add("deformer_move", "D TO", "Moves layer D to place TO among the layers (1 = first): one undo step.",
      [this](std::istringstream& in) {
        size_t d = 0, to = 0;
        if (!(in >> d >> to)) return fail("deformer_move D TO");
        move_deformer(d, to);
      });
  add("deformer_rename", "D NAME", "Renames layer D: one undo step.", [this](std::istringstream& in) {
    size_t d = 0;
    std::string name;
    if (!(in >> d) || !std::getline(in >> std::ws, name)) return fail("deformer_rename D NAME");
    name.erase(name.find_last_not_of(" \t\r") + 1);
    rename_deformer(d, name);
  });
  add("deformer_mask", "D joints a,b,-c | D primitives 0,2 | D meshes body | D none",
      "Layer D's skin mask: these joints' region (feathered by the skin weights; -c leaves one out), these primitives or glTF meshes, or none: one undo step.",
      [this](std::istringstream& in) {
        size_t d = 0;
        std::string kind, list;
        if (!(in >> d >> kind)) return fail("deformer_mask D joints a,b,-c | D primitives 0,2 | D meshes body | D none");
        in >> list;
        if (kind == "none") set_deformer_mask(d, "");
        else if ((kind == "joints" || kind == "primitives" || kind == "meshes") && !list.empty()) set_deformer_mask(d, kind + " " + list);
        else fail("deformer_mask D joints a,b,-c | D primitives 0,2 | D meshes body | D none");
      });
  add("deformer_stack", "in_order|sum|blend [M]", "How the deformers' skins combine (M: the blend's exponent): one undo step.",
      [this](std::istringstream& in) {
        std::string mode;
        in >> mode;
        StackMode m{};
        if (!parse_stack_mode(mode, m)) return fail("deformer_stack in_order|sum|blend [M]");
        double exponent = scene_ ? scene_->work().stack.exponent : 2.0;
        in >> exponent;
        set_stack_mode(m, exponent);
      });
  add("deformer_cancel", "", "Cancels the binds of the deformers other than the active one.", [this](std::istringstream&) {
    if (scene_) scene_->cancel_stack_binds();
  });
  add("deformer_bind", "", "Binds again the deformers whose bind failed or was cancelled.", [this](std::istringstream&) {
    if (scene_) scene_->retry_stack_binds();
  });
}

}  // namespace cagewrap::app
