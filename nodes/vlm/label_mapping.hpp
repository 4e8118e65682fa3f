// A live VLM's free labels onto the vocabulary (issue 30): a reply that says "anesthesia
// workstation" or "OR nurse" instead of the class name would give a label no query and no metric
// can match. Every box label that is not a class name goes through the same mapping as the user's
// queries (vocabulary_match.hpp): near a class, the box takes the class name and its score is
// multiplied by the match score (the box keeps how sure the mapping was); near none, the label
// stays as its own class and is reported.
#pragma once

#include <string>
#include <vector>

#include "nodes/scene/boxes.hpp"
#include "nodes/scene/vocabulary_match.hpp"

namespace gslift {

struct LabelMappingReport {
  // One line per distinct label: "anesthesia workstation -> anesthesia machine (0.87)".
  std::vector<std::string> mapped;
  // One line per distinct label near no class: VocabularyMatcher::explain_miss.
  std::vector<std::string> unmapped;
};

// Rewrites boxes' labels in place; class names (compared without case or extra spaces) are left
// as they are. Each distinct label is matched once.
LabelMappingReport map_box_labels(BoxSet& boxes, const VocabularyMatcher& matcher);

}  // namespace gslift
