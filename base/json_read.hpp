// Every JSON document gslift reads (VLM replies, transforms.json, COCO RLE masks, run.json,
// segment prompts, ...) goes through parse_json. nlohmann's parser is iterative, but dumping,
// copying and comparing a value recurse once per nesting level: a 600 KB VLM reply nested 100,000
// levels deep parsed fine and then overflowed the stack (SIGSEGV, no run.json). parse_json refuses
// such a document before parsing, the way graph/yaml_reader.cpp refuses a graph that expands past
// kMaxYamlValues. The one header in base/ with a dependency (nlohmann_json, itself header-only):
// it is the target gslift_json, so that gslift_base stays standard-library only.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace gslift {

// The deepest nesting of arrays and objects parse_json accepts. gslift's own formats nest at
// most 5 levels; 256 leaves room for any honest document while keeping a recursive walk far from
// the stack limit of a worker thread (and of the sanitizer builds, whose frames are larger).
constexpr size_t kMaxJsonDepth = 256;

// The 1-based byte offset of the bracket that opens level max_depth + 1 of `text`, or 0 if no
// array or object nests deeper. Brackets inside strings do not count. Exact for valid JSON;
// invalid JSON is refused by the parser anyway, wherever this scan stops.
inline size_t json_too_deep_at(std::string_view text, size_t max_depth = kMaxJsonDepth) {
  size_t depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;  // the escaped character, '"' included, does not end the string
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i + 1;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return 0;
}

// nlohmann::json::parse(text), but a document nested deeper than kMaxJsonDepth throws the
// library's own parse_error (so every caller's existing handler names its file), at the byte
// where the nesting goes too deep.
inline nlohmann::json parse_json(std::string_view text) {
  if (const size_t at = json_too_deep_at(text))
    throw nlohmann::json::parse_error::create(101, at,
                                              "arrays and objects nested more than " +
                                                  std::to_string(kMaxJsonDepth) +
                                                  " levels deep; refusing to read it",
                                              nullptr);
  return nlohmann::json::parse(text);
}

// parse_json without exceptions: a discarded value (is_discarded()) for invalid or too deeply
// nested JSON, for callers that skip a bad document rather than fail.
inline nlohmann::json parse_json_or_discarded(std::string_view text) {
  if (json_too_deep_at(text)) return nlohmann::json(nlohmann::json::value_t::discarded);
  return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
}

}  // namespace gslift
