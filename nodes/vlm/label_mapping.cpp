#include "nodes/vlm/label_mapping.hpp"

#include <cstdio>
#include <map>
#include <optional>
#include <set>

#include "base/normalise_text.hpp"

namespace gslift {

LabelMappingReport map_box_labels(BoxSet& boxes, const VocabularyMatcher& matcher) {
  std::set<std::string> names;  // normalised
  for (const std::string& name : matcher.class_names()) names.insert(normalise_text(name));
  LabelMappingReport report;
  std::map<std::string, std::optional<ClassMatch>> seen;
  for (ViewBoxes& view : boxes.views)
    for (Box& box : view.boxes) {
      if (names.count(normalise_text(box.label))) continue;
      auto it = seen.find(box.label);
      if (it == seen.end()) {
        it = seen.emplace(box.label, matcher.match(box.label)).first;
        if (it->second) {
          char score[32];
          std::snprintf(score, sizeof score, "%.2f", it->second->score);
          report.mapped.push_back(box.label + " -> " + it->second->name + " (" + score + ")");
        } else {
          report.unmapped.push_back(matcher.explain_miss(box.label));
        }
      }
      if (it->second) {
        box.label = it->second->name;
        box.score *= it->second->score;
      }
    }
  return report;
}

}  // namespace gslift
