// Prompts as JSON, the form a prompt file and a `gslift segment` session line share:
//   {"name": "chair", "kind": "point", "view": "cam_00",
//    "positive": [[x, y], ...], "negative": [[x, y], ...]}          point / scribble (vertices)
//   {"name": "chair", "kind": "mask" | "sam", "view": "cam_00", "mask": "chair.png"}
// "kind" defaults to mask when "mask" is given, else point; "name" defaults to "prompt_<index>".
// Mask files are 8-bit images, > 127 = the object, relative paths resolved against `base`.
// A prompt file holds a list of such objects (or {"prompts": [...]}), as JSON or, for a file
// ending in .yaml / .yml, the same structure in YAML (a scalar with a leading zero, like the view
// 000000, stays a string).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nodes/scene/prompts.hpp"

namespace gslift {

// Throws InputError starting with `where` and naming the field for a missing view, a field of the
// wrong type, a malformed pixel list, an unknown kind, an unreadable mask file or a field that is
// neither a prompt's nor one of `extra_fields` (e.g. a session line's "output"). Pixel ranges are
// checked later, against the view.
Prompt prompt_from_json(const nlohmann::json& j, const std::filesystem::path& base,
                        const std::string& where, size_t index = 0,
                        const std::vector<std::string>& extra_fields = {});

// A prompt file (JSON or YAML, above). Throws InputError naming the file (and the prompt and
// field) when it cannot be read or parsed or a prompt is malformed.
PromptSet read_prompt_file(const std::filesystem::path& path);

}  // namespace gslift
