#include "nodes/scene/vocabulary.hpp"

namespace gslift {

std::vector<std::string> Vocabulary::class_names() const {
  std::vector<std::string> names;
  for (const auto& e : entities) names.push_back(e.name);
  return names;
}

}  // namespace gslift
