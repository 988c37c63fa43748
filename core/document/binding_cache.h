// A project's binding cached beside it, so that opening the project needs no bind: the .cwb file
// (core/io/binding_io.h) `P.cagewrap.cwb`, recorded in the project with a content hash of the file and
// of every input the bind depends on (BindingInputs in core/document/document.h): the character file, the
// rest cage, the binding parameters, the set edits and, with automatic separation, the attachment
// settings (its part labels), and the program. Opening uses the cache only when every input and
// the file's hash still match; otherwise the caller binds again and can say which input changed.
// docs/project-format.md, "binding_cache".
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/deform/binding.h"
#include "core/document/document.h"
#include "core/base/result.h"

namespace cagewrap {

// Where the cache of the project at `project_path` goes: the project's path + ".cwb" for the document's own
// cage (deformer 0), + ".<d>.cwb" for deformer d (layer d - 1 of the stack, docs/deformer-stack.md).
std::string binding_cache_path(const std::string& project_path, size_t deformer = 0);

// The inputs of binding `doc` as it is now (the document must have a cage: checked).
BindingInputs binding_inputs(const Document& doc);
// The inputs that differ, for a message: "the cage and the binding parameters"; "" when none.
std::string changed_inputs(const BindingInputs& recorded, const BindingInputs& now);

// Whether `binding` is the binding of `doc` as it is: its parameters, its rest cage (bit for bit)
// and its point count. The error says what differs.
Status binding_fits(const Binding& binding, const Document& doc);

// The cache file of `binding` (which must fit `doc`: checked with binding_fits) for the project at
// `project_path`: where it goes, its bytes and the record the project file keeps for it.
// save_project writes it (atomically) just before the project. Errors name the cache file.
struct BindingCacheFile {
  std::string path;
  std::string bytes;
  BindingCacheRecord record;
};
// `doc` is the deformer's view (deformer_document) and `deformer` its number: the cache goes to
// binding_cache_path(project_path, deformer).
Result<BindingCacheFile> make_binding_cache(const std::string& project_path, const Document& doc,
                                            const Binding& binding, size_t deformer = 0);

// The binding the document's project recorded (doc.binding_cache), when it is still valid for
// `doc`: the file exists, has the recorded hash, loads, its inputs equal binding_inputs(doc) and it
// fits the document. The error says why not in one sentence naming the cache file ("... is out of
// date: the binding parameters changed since it was written"): kFileNotFound when nothing is
// cached or the file is gone, kInvalidArgument when it is out of date or was replaced, else the
// load error.
Result<Binding> load_binding_cache(const Document& doc);

// The cached bindings of every deformer of the stack that moves the skin (not muted), each loaded with
// load_binding_cache(deformer_document(doc, d)): bindings[d] for deformer d (nullopt where nothing usable is
// cached), and for each deformer that recorded a cache it cannot use, why (load_binding_cache's sentence).
struct StackBindingCache {
  std::vector<std::optional<Binding>> bindings;  // #deformers
  std::vector<std::string> not_used;
  size_t used = 0;  // how many bindings came from the cache
};
StackBindingCache load_stack_binding_caches(const Document& doc);

}  // namespace cagewrap
