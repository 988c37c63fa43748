// Moving a project's character into the project file and back out (docs/project-format.md,
// "character.embedded"): an embedded project opens with no other file; taking the character out
// again writes its bytes, unchanged, to a file the project then names.
#pragma once

#include <string>

#include "core/document/document.h"
#include "core/base/result.h"

namespace cagewrap {

// The document embedding its character file: reads character_path, checks that it is still the
// file the document was made from (its content hash) and that it loads with no other file (a .glb,
// or a .gltf with data: URIs; load_character_bytes). Already embedded: returned unchanged. Errors
// name the file.
Result<Document> embed_character(const Document& doc);

// The document naming `path` instead of embedding its character: writes the embedded bytes there
// (atomically) unless the file already holds exactly these bytes. An existing other file is
// replaced only with `replace` (the editor's file browser has asked). Refuses the project file
// itself. Not embedded: an error.
Result<Document> unembed_character(const Document& doc, const std::string& path, bool replace);

}  // namespace cagewrap
