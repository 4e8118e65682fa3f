#include "nodes/scene/context_prompt.hpp"

#include <cctype>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "base/errors.hpp"

namespace gslift {
namespace {

std::string where(const std::string& source, const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  return source + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

std::string text_field(const std::string& source, const YAML::Node& entry, const std::string& key,
                       const std::string& what) {
  const YAML::Node value = entry[key];
  if (!value || !value.IsScalar() || value.Scalar().empty())
    throw InputError(where(source, value ? value : entry) + ": " + what + " has no " + key +
                     (key == "name" ? "" : " context"));
  return value.Scalar();
}

EntityContext parse_entity(const std::string& source, const YAML::Node& entry,
                           std::set<std::string>& names) {
  if (!entry.IsMap()) throw InputError(where(source, entry) + ": a class must be a mapping");
  static const std::set<std::string> known{"name",       "kind",    "spatial",    "behaviour",
                                           "appearance", "aliases", "description"};
  std::set<std::string> seen;  // yaml-cpp keeps the last of duplicate keys silently
  for (const auto& kv : entry) {
    const std::string key = kv.first.as<std::string>();
    if (!known.count(key))
      throw InputError(where(source, kv.first) + ": unknown key '" + key +
                       "' (name, kind, spatial, behaviour, appearance)");
    if (!seen.insert(key).second)
      throw InputError(where(source, kv.first) + ": key '" + key + "' appears twice");
  }
  EntityContext e;
  e.name = text_field(source, entry, "name", "a class");
  for (char& c : e.name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::string what = "class '" + e.name + "'";
  if (!names.insert(e.name).second)
    throw InputError(where(source, entry["name"]) + ": " + what + " is defined twice");
  const std::string kind = text_field(source, entry, "kind", what);
  if (kind != "person" && kind != "object")
    throw InputError(where(source, entry["kind"]) + ": " + what + " has kind '" + kind +
                     "' (person, object)");
  e.person = kind == "person";
  e.spatial = text_field(source, entry, "spatial", what);
  e.appearance = text_field(source, entry, "appearance", what);
  if (e.person) {
    e.behaviour = text_field(source, entry, "behaviour", what);
  } else if (entry["behaviour"]) {
    throw InputError(where(source, entry["behaviour"]) + ": " + what +
                     " is an object; behaviour context is for people only");
  }
  if (entry["description"]) e.description = text_field(source, entry, "description", what);
  if (const YAML::Node aliases = entry["aliases"]) {
    if (!aliases.IsSequence())
      throw InputError(where(source, aliases) + ": " + what + ": aliases must be a list");
    for (const YAML::Node& a : aliases) {
      if (!a.IsScalar() || a.Scalar().empty())
        throw InputError(where(source, a) + ": " + what + ": an alias must be a non-empty text");
      e.aliases.push_back(a.Scalar());
    }
  }
  return e;
}

}  // namespace

Vocabulary parse_vocabulary(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InputError(source + ":" + std::to_string(e.mark.line + 1) + ":" +
                     std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  if (!root.IsMap() || !root["classes"])
    throw InputError(source + ": no 'classes' list (see graphs/vocabulary/or.yaml)");
  const YAML::Node classes = root["classes"];
  if (!classes.IsSequence() || classes.size() == 0)
    throw InputError(where(source, classes) + ": 'classes' must be a non-empty list");
  Vocabulary v;
  v.source = source;
  std::set<std::string> names;
  for (const auto& entry : classes) v.entities.push_back(parse_entity(source, entry, names));
  v.prompt = build_prompt(v);
  return v;
}

Vocabulary load_vocabulary(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot read the vocabulary file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_vocabulary(text.str(), path.string());
}

std::string build_prompt(const Vocabulary& vocabulary) {
  std::ostringstream p;
  p << "This image comes from a camera mounted high in an operating room. Find every visible "
       "instance of the entities below and ground each one with a bounding box. Use the context "
       "of each entity to tell similar ones apart: where it is, what it looks like, and for "
       "people, what they are doing.\n\nEntities:\n";
  int index = 1;
  for (const auto& e : vocabulary.entities) {
    p << index++ << ". " << e.name << (e.person ? " (person)" : " (object)") << "\n"
      << "   Where: " << e.spatial << "\n";
    if (e.person) p << "   Doing: " << e.behaviour << "\n";
    p << "   Looks like: " << e.appearance << "\n";
  }
  p << "\nRules:\n"
       "- One box per instance, tight around the visible part; several people may share a role.\n"
       "- The label must be exactly one of the entity names above.\n"
       "- Skip entities that are not visible; do not guess.\n"
       "Answer with JSON only:\n"
       "```json\n"
       "[{\"bbox_2d\": [x1, y1, x2, y2], \"label\": \"<entity name>\"}]\n"
       "```\n";
  return p.str();
}

}  // namespace gslift
