// embedded:or specs, the settings-keyed cache, and the round trip through ingest's reader.
#include <cstdlib>

#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "nodes/synth/embedded_capture.hpp"
#include "nodes/synth/register.hpp"
#include "runtime/node.hpp"
#include "runtime/registry.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::synth;
namespace fs = std::filesystem;

TEST_CASE("embedded specs parse into settings, bad specs name the problem") {
  const OrCaptureSettings s = parse_embedded_spec("or?seed=3&phase=closing&preset=hard");
  CHECK(s.scene.seed == 3);
  CHECK(s.scene.phase == OrPhase::Closing);
  CHECK(s.knobs.vlm_miss_rate == preset_knobs(SynthPreset::Hard).vlm_miss_rate);
  CHECK(parse_embedded_spec("or").scene.seed == 0);
  CHECK_THROWS_AS(parse_embedded_spec("kitchen"), InputError);
  CHECK_THROWS_WITH(parse_embedded_spec("or?seed"), Catch::Contains("name=value"));
  CHECK_THROWS_WITH(parse_embedded_spec("or?vlm_miss_rate=2"), Catch::Contains("vlm_miss_rate"));
  CHECK_THROWS_WITH(parse_embedded_spec("or?width=100000&height=100000"),
                    Catch::Contains("embedded:or?width=100000&height=100000: width x height"));
}

TEST_CASE("the cache folder is keyed by every setting") {
  const fs::path cache = "/c";
  const auto a = cached_capture_folder(parse_embedded_spec("or?seed=1"), cache);
  CHECK(a == cached_capture_folder(parse_embedded_spec("or?seed=1&preset=default"), cache));
  CHECK(a != cached_capture_folder(parse_embedded_spec("or?seed=2"), cache));
  CHECK(a != cached_capture_folder(parse_embedded_spec("or?seed=1&depth_noise=0.03"), cache));
  CHECK(a != cached_capture_folder(parse_embedded_spec("or?seed=1&width=320"), cache));
  CHECK(a.parent_path() == cache / "embedded");
  CHECK(a.filename().string().rfind("or_s1_surgery-", 0) == 0);
}

TEST_CASE("embedded:or resolves to a generated capture that ingest reads with ground truth") {
  const fs::path cache = test::scratch_dir("synth_cache");
  ::setenv("GSLIFT_CACHE", cache.c_str(), 1);
  Registry registry;
  register_synth_nodes(registry);
  REQUIRE(registry.find("synth.capture") != nullptr);
  const fs::path folder = resolve_capture_path("embedded:or?width=96&height=72&seed=2");
  ::unsetenv("GSLIFT_CACHE");
  CHECK(folder.parent_path() == cache / "embedded");
  const auto written = fs::last_write_time(folder / "capture.yaml");
  // A second request reuses the cached folder instead of generating again.
  CHECK(ensure_cached_capture(parse_embedded_spec("or?width=96&height=72&seed=2"), cache) ==
        folder);
  CHECK(fs::last_write_time(folder / "capture.yaml") == written);

  const Capture c = load_capture(folder);
  REQUIRE(c.views.size() == 5);
  CHECK(c.test_views() == std::vector<int>{4});
  CHECK(c.classes.size() == 12);
  CHECK(c.classes.at(kAnesthesiaMachine) == "anesthesia machine");
  CHECK(c.instance_class.size() >= 12);
  CHECK(c.points.size() > 1000);
  const OrScene scene = make_or_scene(parse_embedded_spec("or?width=96&height=72&seed=2").scene);
  for (size_t i = 0; i < c.views.size(); ++i) {
    const View& v = c.views[i];
    CHECK(v.name == scene.cameras[i].name);
    CHECK(v.camera.fx == Approx(scene.cameras[i].camera.fx));
    CHECK(v.pose.R.isApprox(scene.cameras[i].pose.R, 1e-12));
    const cv::Mat inst = v.gt_instance.load();
    REQUIRE(inst.type() == CV_32SC1);
    REQUIRE(inst.size() == cv::Size(96, 72));
    const cv::Mat depth = v.depth.load(), gt = v.gt_depth.load();
    REQUIRE(depth.type() == CV_32FC1);
    CHECK(cv::countNonZero(gt > 0) == 96 * 72);
    CHECK(v.gt_normal.load().type() == CV_32FC3);
  }
}
