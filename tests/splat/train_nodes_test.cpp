// splat.reconstruct and splat.render through the executor, on an inline graph.
#include <fstream>
#include <sstream>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "nodes/splat/ply_io.hpp"
#include "nodes/splat/register.hpp"
#include "runtime/executor.hpp"
#include "tests/splat/train_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

Registry registry_with_tiny_capture() {
  Registry r;
  register_splat_nodes(r);
  r.add(NodeSpec{"test.tiny_capture",
                 "the rendered 5-view capture of train_scene.hpp",
                 {},
                 {{"capture", "Capture", "the capture"}},
                 {}},
        [](NodeContext& ctx) { ctx.output("capture", test::rendered_capture()); });
  r.add(NodeSpec{"test.tiny_photos",
                 "the same capture without its depth prior (plain photos)",
                 {},
                 {{"capture", "Capture", "the capture"}},
                 {}},
        [](NodeContext& ctx) {
          Capture c = test::rendered_capture();
          for (View& v : c.views) v.depth = ImageSource();
          ctx.output("capture", std::move(c));
        });
  r.add(NodeSpec{"test.tiny_renamed",
                 "the same capture with other view names",
                 {},
                 {{"capture", "Capture", "the capture"}},
                 {}},
        [](NodeContext& ctx) {
          Capture c = test::rendered_capture();
          for (View& v : c.views) v.name = "other_" + v.name;
          ctx.output("capture", std::move(c));
        });
  return r;
}

}  // namespace

TEST_CASE("splat.reconstruct writes model.ply and records its numbers, splat.render writes PNGs") {
  const Registry registry = registry_with_tiny_capture();
  RunOptions options;
  options.out_dir = test::scratch_dir("train_nodes");
  const RunResult run = run_graph_text(R"(
graph: tiny
nodes:
  capture: {type: test.tiny_capture}
  recon:   {type: splat.reconstruct, in: {capture: capture.capture},
            params: {iterations: 60, feature_dim: 4}}
  render:  {type: splat.render, in: {model: recon.model, capture: capture.capture},
            params: {channels: [rgb, depth, normal, alpha, features], views: all}}
)",
                                       registry, options);
  INFO((run.error ? run.error->str() : std::string()));
  REQUIRE(run.ok());
  const NodeRecord* recon = run.node("recon");
  REQUIRE(recon);
  const double gaussians = std::get<double>(recon->records.at("gaussians"));
  CHECK(gaussians > 0);
  CHECK(std::get<double>(recon->records.at("train_psnr")) > 15);
  CHECK(recon->records.count("test_psnr") == 1);
  CHECK(std::get<double>(recon->records.at("iterations_run")) == 60);
  // The phases' wall seconds: each measured, together no more than the whole reconstruction.
  double phases = 0;
  for (const char* phase : {"prepare", "render", "losses", "backward", "adam", "density"}) {
    INFO(phase);
    const double seconds = std::get<double>(recon->records.at(std::string(phase) + "_seconds"));
    CHECK(seconds >= 0);
    phases += seconds;
  }
  CHECK(std::get<double>(recon->records.at("render_seconds")) > 0);
  CHECK(phases <= std::get<double>(recon->records.at("seconds")));
  // Each term's share of the losses phase: the photometric term ran at every step.
  const double photometric = std::get<double>(recon->records.at("term_seconds/photometric"));
  CHECK(photometric > 0);
  CHECK(photometric <= std::get<double>(recon->records.at("losses_seconds")));

  const GaussianModel model = read_ply(options.out_dir / "recon" / "model.ply");
  CHECK(model.size() == static_cast<size_t>(gaussians));
  CHECK(model.feature_dim == 4);
  CHECK(model.sh_degree == 1);
  for (const char* c : {"rgb", "depth", "normal", "alpha", "features"})
    for (int v = 0; v < 5; ++v)
      CHECK(std::filesystem::exists(options.out_dir / "render" /
                                    ("cam_" + std::to_string(v) + "_" + c + ".png")));
}

TEST_CASE("the depth_prior recipe on plain photos says its depth levers do nothing there",
          "[long]") {
  const Registry registry = registry_with_tiny_capture();
  std::ostringstream log;
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(log);
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", sink));
  const auto run_on = [&](const std::string& source) {
    return run_graph_text("graph: tiny\nnodes:\n  capture: {type: " + source +
                              "}\n  recon: {type: splat.reconstruct, in: {capture: "
                              "capture.capture}, params: {iterations: 20, recipe: depth_prior, "
                              "min_train_psnr: 0}}\n",
                          registry, RunOptions{});
  };
  const RunResult photos = run_on("test.tiny_photos");
  const std::string photos_log = log.str();
  log.str("");
  const RunResult rgbd = run_on("test.tiny_capture");
  spdlog::set_default_logger(previous);
  REQUIRE(photos.ok());
  REQUIRE(rgbd.ok());
  CHECK(std::get<double>(photos.node("recon")->records.at("depth_prior_views")) == 0);
  CHECK(std::get<double>(rgbd.node("recon")->records.at("depth_prior_views")) == 4);
  // reconstruct() warns, so joint training through it (features.view_classifiers) does too.
  CHECK_THAT(photos_log, Catch::Matchers::Contains("no training view has a depth prior, so "
                                                   "line_of_sight_weight, edge_extent_weight, "
                                                   "prune_line_of_sight"));
  CHECK(log.str().find("no training view has a depth prior") == std::string::npos);
}

TEST_CASE("splat.load reads a model written by splat.reconstruct, and names a missing file") {
  const Registry registry = registry_with_tiny_capture();
  RunOptions options;
  options.out_dir = test::scratch_dir("train_nodes_load");
  GaussianModel saved = test::ground_truth_scene();
  saved.feature_dim = 3;
  saved.features.assign(saved.size() * 3, 0.25f);
  const auto path = options.out_dir / "saved.ply";
  write_ply(saved, path);
  const RunResult run = run_graph_text(R"(
graph: load
nodes:
  capture: {type: test.tiny_capture}
  model:   {type: splat.load, params: {path: ")" +
                                           path.string() + R"("}}
  render:  {type: splat.render, in: {model: model.model, capture: capture.capture},
            params: {channels: [rgb, features], views: test}}
)",
                                       registry, options);
  INFO((run.error ? run.error->str() : std::string()));
  REQUIRE(run.ok());
  CHECK(std::get<double>(run.node("model")->records.at("gaussians")) ==
        static_cast<double>(saved.size()));
  CHECK(std::get<double>(run.node("model")->records.at("feature_dim")) == 3);

  const RunResult missing = run_graph_text(R"(
graph: missing
nodes:
  model: {type: splat.load, params: {path: /nonexistent/model.ply}}
)",
                                           registry, options);
  REQUIRE_FALSE(missing.ok());
  CHECK_THAT(missing.error->str(), Catch::Contains("/nonexistent/model.ply"));
}

TEST_CASE(
    "splat.refined_capture hands on the poses splat.reconstruct refined, and refuses another "
    "capture's") {
  const Registry registry = registry_with_tiny_capture();
  RunOptions options;
  options.out_dir = test::scratch_dir("train_nodes_poses");
  const std::string graph = R"(
graph: poses
nodes:
  capture: {type: test.tiny_capture}
  other:   {type: test.tiny_renamed}
  recon:   {type: splat.reconstruct, in: {capture: capture.capture},
            params: {iterations: 40, refine_poses: true, pose_held_out_steps: 10}}
  posed:   {type: splat.refined_capture, in: {capture: CAPTURE.capture, poses: recon.poses}}
  render:  {type: splat.render, in: {model: recon.model, capture: posed.capture}}
)";
  const auto with = [&](const std::string& capture) {
    std::string text = graph;
    text.replace(text.find("CAPTURE"), 7, capture);
    return text;
  };
  const RunResult run = run_graph_text(with("capture"), registry, options);
  INFO((run.error ? run.error->str() : std::string()));
  REQUIRE(run.ok());
  const auto& records = run.node("recon")->records;
  // The true poses move a little (the model is wrong early on); each record is a real change.
  CHECK(std::get<double>(records.at("pose_change/train/degrees_mean")) > 0);
  CHECK(std::get<double>(records.at("pose_change/held_out/centre_max")) > 0);
  // The registration's time is its own record, within the reconstruction's.
  const double registration = std::get<double>(records.at("held_out_poses_seconds"));
  CHECK(registration > 0);
  CHECK(registration < std::get<double>(records.at("seconds")));
  std::ifstream poses(options.out_dir / "recon" / "refined_poses.txt");
  std::string line;
  int views = 0;
  while (std::getline(poses, line))
    if (line.rfind("cam_", 0) == 0) ++views;
  CHECK(views == 5);

  const RunResult mismatched = run_graph_text(with("other"), registry, RunOptions{});
  REQUIRE_FALSE(mismatched.ok());
  CHECK_THAT(mismatched.error->str(),
             Catch::Matchers::Contains("port 'poses' names view 'cam_0' where capture 'tiny' has "
                                       "'other_cam_0'"));
}
