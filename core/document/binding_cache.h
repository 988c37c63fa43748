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
// The same for the parametric drivers that move the skin: drivers[i] for driver i (driver_at's number).
struct StackBindingCache {
  std::vector<std::optional<Binding>> bindings;  // #deformers
  std::vector<std::optional<Binding>> drivers;   // #drivers
  std::vector<std::string> not_used;
  size_t used = 0;          // how many deformers' bindings came from the cache
  size_t drivers_used = 0;  // how many drivers' bindings came from the cache
};
StackBindingCache load_stack_binding_caches(const Document& doc);

// The parametric drivers' caches (issue 21): driver i (driver_at's number) is bound to the samples of its
// rest surface (core/deform/patch_binding.h), and its binding is cached as a cage's is, in
// `P.cagewrap.D<i + 1>.cwb`, recorded in its DriverPlacement::binding_cache. Its inputs: the character
// file, the rest surface with its density (in BindingInputs::cage), the parameters it binds with
// (patch_bind_params of driver_params), its set edits (sample ids) and the program; the attachment is
// not an input (it does not reach the bind).
std::string driver_binding_cache_path(const std::string& project_path, size_t driver);
// i < driver_count(doc): checked.
BindingInputs driver_binding_inputs(const Document& doc, size_t driver);
// Whether `binding` is driver i's as the document has it: the parameters, the sample count, the point count.
Status driver_binding_fits(const Binding& binding, const Document& doc, size_t driver);
Result<BindingCacheFile> make_driver_binding_cache(const std::string& project_path, const Document& doc, size_t driver,
                                                   const Binding& binding);
// Driver i's cached binding when its record is still valid (load_binding_cache's rules and errors).
Result<Binding> load_driver_binding_cache(const Document& doc, size_t driver);

}  // namespace cagewrap
