// The vocabulary of OR entity classes with their contexts (LangOR §1.1 context-aware prompting):
// what boxes.prompt loads from YAML (nodes/scene/context_prompt.hpp) and the VLM is prompted with.
#pragma once

#include <string>
#include <vector>

#include "base/port_type.hpp"

namespace gslift {

struct EntityContext {
  std::string name;        // class name, lower case, unique in the vocabulary
  bool person = false;     // kind: person (has a behaviour context) or object
  std::string spatial;     // where the entity is in the room
  std::string behaviour;   // what the person does; empty for objects
  std::string appearance;  // what it looks like
  // Optional, for matching the user's words onto the class (nodes/text/lexical_matcher.hpp), not
  // sent to the VLM: other names for it and a short plain description.
  std::vector<std::string> aliases{};
  std::string description{};
};

struct Vocabulary {
  std::string source;                   // the file it came from (for messages)
  std::vector<EntityContext> entities;  // in file order
  std::string prompt;                   // build_prompt(*this), filled by the loaders

  std::vector<std::string> class_names() const;
};

GSLIFT_PORT_TYPE(Vocabulary, "Vocabulary");

}  // namespace gslift
