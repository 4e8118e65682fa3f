#include "nodes/inference/growth_exclusion.hpp"

#include <string>

#include "base/errors.hpp"
#include "nodes/inference/mask_silhouette.hpp"

namespace gslift {

GrowthExclusion prompt_growth_exclusion(const std::vector<float>& means, const Capture& capture,
                                        const PromptSet& prompts, double outside_vote) {
  const size_t n = means.size() / 3;
  GrowthExclusion excluded;
  for (size_t k = 0; k < prompts.prompts.size(); ++k) {
    const Prompt& p = prompts.prompts[k];
    std::vector<char> out;
    if (!p.mask.empty()) {
      const int v = capture.find_view(p.view);
      if (v < 0)
        throw InputError("prompt '" + p.name + "': the capture has no view '" + p.view + "'");
      out = centres_outside_mask(means, capture.views[v], p.mask);
    }
    if (k < prompts.vote_balance.size() && !prompts.vote_balance[k].empty() && outside_vote < 1) {
      const std::vector<float>& balance = prompts.vote_balance[k];
      if (balance.size() != n)
        throw InputError("prompt '" + p.name + "' was voted on a model of " +
                         std::to_string(balance.size()) + " Gaussians, this one has " +
                         std::to_string(n));
      out.resize(n, 0);
      for (size_t g = 0; g < n; ++g) out[g] |= balance[g] < -outside_vote;
    }
    if (!out.empty()) excluded[static_cast<int32_t>(k)] = std::move(out);
  }
  return excluded;
}

}  // namespace gslift
