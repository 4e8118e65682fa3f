// When a reconstruction is no result (nodes/splat/reconstruction_check.hpp), on hand-built
// results.
#include "nodes/splat/reconstruction_check.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

namespace {

ReconstructResult with_gaussians(size_t n, double train_psnr) {
  ReconstructResult r;
  r.model.opacity_logits.assign(n, 0.f);  // size() counts opacities
  r.train_psnr = train_psnr;
  r.iterations_run = 500;
  r.scene_extent = 0.122;
  return r;
}

}  // namespace

TEST_CASE("an empty reconstruction names the pruning round that emptied it") {
  ReconstructResult r = with_gaussians(0, 4.1);
  r.initial_gaussians = 2756;
  r.emptied = ReconstructResult::Emptied{100, 0, 2756, 0};
  const std::string why = reconstruction_failure(r, kDefaultMinTrainPsnr);
  CHECK(why ==
        "the reconstruction ended with 0 Gaussians (2756 at the start, scene extent 0.122): the "
        "pruning round at step 100 removed the last ones, 2756 larger than prune_max_scale x "
        "scene extent, 0 below prune_opacity, 0 by free-space pruning");
  // No floor makes an empty model acceptable.
  CHECK_FALSE(reconstruction_failure(r, 0).empty());
}

TEST_CASE("a train PSNR under the floor fails, at or above it, or with no floor, it is a result") {
  CHECK_THAT(reconstruction_failure(with_gaussians(10, 4.1), 10),
             Contains("train PSNR is 4.1 dB, under the floor min_train_psnr = 10.0 dB") &&
                 Contains("10 Gaussians after 500 steps"));
  CHECK(reconstruction_failure(with_gaussians(10, 10.0), 10).empty());
  CHECK(reconstruction_failure(with_gaussians(10, 4.1), 0).empty());
  // No training view: no PSNR to judge.
  CHECK(reconstruction_failure(with_gaussians(10, std::nan("")), 10).empty());
}
