#include "nodes/synth/drapes.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

Material drape_material() {
  return {Eigen::Vector3f(0.26f, 0.44f, 0.62f), Texture::Flat};
}

std::set<int> drape_equipment(OrScene& scene, double fraction, uint64_t seed) {
  if (!(fraction >= 0 && fraction <= 1)) {
    throw std::invalid_argument("drapes must be in [0, 1], got " + std::to_string(fraction));
  }
  std::vector<int> equipment;
  for (const auto& [instance, cls] : scene.instance_class) {
    const bool person = is_look_alike_class(cls) || cls == kPatient;
    if (!person && cls != kSurgicalLamp) equipment.push_back(instance);
  }
  const auto count = static_cast<size_t>(std::lround(fraction * double(equipment.size())));
  if (count == 0) return {};
  // Fisher-Yates with the capture's own drape stream: the layout and sensor draws never move.
  RandomStream rng(stream_seed(seed, kDrapeStream));
  for (size_t i = equipment.size(); i > 1; --i)
    std::swap(equipment[i - 1], equipment[rng.below(i)]);
  const std::set<int> draped(equipment.begin(), equipment.begin() + count);
  for (Primitive& p : scene.primitives)
    if (draped.count(p.instance)) p.material = drape_material();
  return draped;
}

}  // namespace gslift::synth
