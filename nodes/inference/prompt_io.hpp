// Prompts as JSON, the form a prompt file and a `gslift segment` session line share:
//   {"name": "chair", "kind": "point", "view": "cam_00",
//    "positive": [[x, y], ...], "negative": [[x, y], ...]}          point / scribble (vertices)
//   {"name": "chair", "kind": "mask" | "sam", "view": "cam_00", "mask": "chair.png"}
// "kind" defaults to mask when "mask" is given, else point; "name" defaults to "prompt_<index>".
// Mask files are 8-bit images, > 127 = the object, relative paths resolved against `base`.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "nodes/scene/prompts.hpp"

namespace gslift {

// Throws InputError starting with `where` for a missing view, a malformed pixel list, an unknown
// kind or an unreadable mask file. Pixel ranges are checked later, against the view.
Prompt prompt_from_json(const nlohmann::json& j, const std::filesystem::path& base,
                        const std::string& where, size_t index = 0);

// A prompt file: a JSON list of prompts, or {"prompts": [...]}.
PromptSet read_prompt_file(const std::filesystem::path& path);

}  // namespace gslift
