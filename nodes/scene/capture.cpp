#include "nodes/scene/capture.hpp"

namespace gslift {

std::vector<int> Capture::train_views() const {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(views.size()); ++i)
    if (!views[i].held_out) out.push_back(i);
  return out;
}

std::vector<int> Capture::test_views() const {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(views.size()); ++i)
    if (views[i].held_out) out.push_back(i);
  return out;
}

const EnumNames<ViewSet>& view_set_names() {
  static const EnumNames<ViewSet> names = {
      {ViewSet::Train, "train"}, {ViewSet::Test, "test"}, {ViewSet::All, "all"}};
  return names;
}

std::vector<int> Capture::views_named(ViewSet which) const {
  if (which == ViewSet::Train) return train_views();
  if (which == ViewSet::Test) return test_views();
  std::vector<int> all(views.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return all;
}

int Capture::find_view(const std::string& n) const {
  for (int i = 0; i < static_cast<int>(views.size()); ++i)
    if (views[i].name == n) return i;
  return -1;
}

}  // namespace gslift
