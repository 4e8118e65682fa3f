// LangOR §1.1 context-aware prompting: every OR entity class carries a spatial context (where it
// is), a behaviour context (people only: what they do) and a visual-appearance context (what it
// looks like). The vocabulary ships as an editable YAML file (graphs/vocabulary/or.yaml):
//
//   classes:
//     - name: head surgeon          # the label the VLM must use
//       kind: person                # person | object
//       spatial: ...                # required
//       behaviour: ...              # required for people, not allowed for objects
//       appearance: ...             # required
//       aliases: [lead surgeon]     # optional: other names, for matching the user's words
//       description: ...            # optional: a short plain description, likewise
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "nodes/scene/vocabulary.hpp"

namespace gslift {

// Parses YAML text; `source` names it in errors. Throws InputError "<source>:<line>:<col>: ..."
// for a missing or empty context, behaviour on an object, an unknown key or kind, a duplicate or
// empty name, or no classes at all.
Vocabulary parse_vocabulary(const std::string& yaml_text, const std::string& source);
// Reads and parses a file (InputError when unreadable).
Vocabulary load_vocabulary(const std::filesystem::path& path);

// The grounding prompt: one numbered entry per class with its three contexts, then the output
// contract of Qwen-VL grounding, a JSON list [{"bbox_2d": [x1, y1, x2, y2], "label": "..."}] with
// labels restricted to the class names.
std::string build_prompt(const Vocabulary& vocabulary);

}  // namespace gslift
