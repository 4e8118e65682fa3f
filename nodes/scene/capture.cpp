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

std::vector<int> Capture::views_named(const std::string& which) const {
  if (which == "train") return train_views();
  if (which == "test") return test_views();
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
