#include "nodes/synth/or_capture.hpp"

#include <atomic>
#include <climits>
#include <functional>
#include <limits>
#include <locale>
#include <sstream>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <unistd.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "base/atomic_file.hpp"
#include "base/utf8.hpp"
#include "nodes/ingest/colmap_model.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/scene/camera.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/synth/bvh.hpp"
#include "nodes/synth/depth_prior_simulator.hpp"
#include "nodes/synth/drapes.hpp"
#include "nodes/synth/pose_noise.hpp"
#include "nodes/synth/render_view.hpp"
#include "nodes/synth/sam_auto_simulator.hpp"
#include "nodes/synth/sam_box_simulator.hpp"
#include "nodes/synth/stream_purpose.hpp"
#include "nodes/synth/visible_instances.hpp"
#include "nodes/synth/vlm_simulator.hpp"

namespace gslift::synth {

namespace fs = std::filesystem;

namespace {

std::ostringstream classic_stream() {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(17);
  return s;
}

std::string classes_yaml(const OrScene& scene) {
  std::ostringstream y = classic_stream();
  y << "classes:\n";
  for (const auto& [id, name] : or_class_names()) y << "  " << id << ": \"" << name << "\"\n";
  y << "instances:\n";
  for (const auto& [inst, cls] : scene.instance_class) y << "  " << inst << ": " << cls << "\n";
  return y.str();
}

// `layout`: the lines that name the views (a COLMAP model or an OR rig time step).
std::string capture_yaml(const OrCaptureSettings& s, const OrScene& scene,
                         const std::string& layout,
                         const std::function<std::string(int)>& view_name) {
  std::ostringstream y = classic_stream();
  y << "format: gslift.capture/v1\n"
    << "name: " << capture_name(s) << "\n"
    << layout << "held_out: [";
  bool first = true;
  for (size_t i = 0; i < scene.cameras.size(); ++i) {
    if (!scene.cameras[i].held_out) continue;
    y << (first ? "" : ", ") << view_name(static_cast<int>(i));
    first = false;
  }
  y << "]\n"
    << "vlm:\n  folder: vlm\n  rounds: " << s.knobs.vlm_rounds << "\n  coords: norm1000\n"
    << "  input_size: [" << s.scene.width << ", " << s.scene.height << "]\n"
    << "sam_box: sam_box\nsam_auto: sam_auto\ngt: gt\n";
  return y.str();
}

std::string synth_yaml(const OrCaptureSettings& s) {
  std::ostringstream y = classic_stream();
  y << "# Settings this capture was generated with (gslift synth); same settings, same bytes.\n"
    << "generator: gslift.synth/v1\n";
  for (const auto& [k, v] : settings_entries(s)) y << k << ": " << v << "\n";
  return y.str();
}

// Everything generated for one view.
struct ViewOutput {
  SparsePoints points;
};

void write_view(const OrCaptureSettings& s, const OrScene& scene, const std::set<int>& draped,
                const Bvh& bvh, int index, int points_per_view, const fs::path& dir,
                ViewOutput& out) {
  const OrCamera& cam = scene.cameras[index];
  const SynthKnobs& k = s.knobs;
  const uint64_t seed = s.scene.seed;
  RenderOptions ro;
  ro.shadows = k.shadows;
  const RenderedView r = render_view(scene, bvh, cam.camera, cam.pose, ro);
  const std::string stem = cam.name;

  write_rgb_png(dir / "images" / (stem + ".png"), r.rgb);
  write_ground_truth(r, stem, dir, k.world_scale);
  RandomStream depth_rng(stream_seed(seed, kDepthPriorStream, index));
  write_depth_png_mm(dir / "depth" / (stem + ".png"),
                     simulate_depth_prior(r.depth, k.depth_noise, k.depth_holes, depth_rng));
  write_model_outputs(s, scene, index, r, stem, dir);

  // Sparse points: random pixels of the training views back-projected with the exact depth,
  // displaced along the ray by the depth-prior noise level (an MVS point cloud's error). SfM
  // finds no features on a textureless drape: its pixels give no point (the draws stay the same).
  if (cam.held_out) return;
  RandomStream pts_rng(stream_seed(seed, kSparsePointStream, index));
  const Eigen::Vector3d centre = cam.pose.centre();
  for (int i = 0; i < points_per_view; ++i) {
    const int u = pts_rng.below(r.depth.cols), v = pts_rng.below(r.depth.rows);
    const float d = r.depth.at<float>(v, u);
    const double noise = pts_rng.normal(0, k.depth_noise);
    if (d <= 0 || draped.count(r.instance.at<int>(v, u))) continue;
    const Eigen::Vector3d ray_cam((u + 0.5 - cam.camera.cx) / cam.camera.fx,
                                  (v + 0.5 - cam.camera.cy) / cam.camera.fy, 1.0);
    const Eigen::Vector3d x = centre + cam.pose.R.transpose() * ray_cam * (d * (1 + noise));
    const cv::Vec3b c = r.rgb.at<cv::Vec3b>(v, u);
    out.points.xyz.push_back((x * k.world_scale).cast<float>());
    out.points.rgb.emplace_back(c[0], c[1], c[2]);
  }
}

}  // namespace

void write_ground_truth(const RenderedView& r, const std::string& stem, const fs::path& dir,
                        double world_scale) {
  write_label_png16(dir / "gt" / "instance" / (stem + ".png"), r.instance);
  write_label_png16(dir / "gt" / "semantic" / (stem + ".png"), r.semantic);
  write_depth_tiff(dir / "gt" / "depth" / (stem + ".tiff"),
                   world_scale == 1 ? r.depth : cv::Mat(r.depth * world_scale));
  write_float_tiff(dir / "gt" / "normal" / (stem + ".tiff"), r.normal);
}

void write_model_outputs(const OrCaptureSettings& s, const OrScene& scene, int index,
                         const RenderedView& r, const std::string& stem, const fs::path& dir) {
  const SynthKnobs& k = s.knobs;
  const uint64_t seed = s.scene.seed;
  // VLM rounds and the SAM masks prompted with each round's boxes, in the same order.
  const auto visible = visible_instances(r.instance, scene.instance_class, k.vlm_min_visible);
  const auto rounds =
      simulate_vlm(visible, r.rgb.cols, r.rgb.rows, k, stream_seed(seed, kVlmStream, index));
  const std::vector<int> pixels =
      count_labels(r.instance, cv::Rect(0, 0, r.instance.cols, r.instance.rows));
  for (size_t q = 0; q < rounds.size(); ++q) {
    const std::string round = "round_" + std::to_string(q);
    write_file_atomically(dir / "vlm" / stem / (round + ".txt"), rounds[q].reply);
    RandomStream sam_rng(stream_seed(seed, kSamBoxStream, index * 1000 + q));
    nlohmann::json masks = nlohmann::json::array();
    for (const VlmBox& b : rounds[q].boxes) {
      const SamBoxMask m = simulate_sam_box(b.box, r.instance, pixels, k, sam_rng);
      masks.push_back(
          sam_mask_record(m.mask, sam_rng.uniform(0.85, 1.0), sam_rng.uniform(0.9, 1.0)));
    }
    write_file_atomically(dir / "sam_box" / stem / (round + ".json"), masks.dump());
  }

  RandomStream auto_rng(stream_seed(seed, kSamAutoStream, index));
  nlohmann::json autos = nlohmann::json::array();
  for (const AutoMask& a : simulate_sam_auto(r.instance, r.part, k, auto_rng)) {
    nlohmann::json rec = sam_mask_record(a.mask, a.predicted_iou, a.stability_score);
    rec["granularity"] = a.granularity;
    autos.push_back(std::move(rec));
  }
  write_file_atomically(dir / "sam_auto" / (stem + ".json"), autos.dump());
}

void write_capture_files(const OrCaptureSettings& s, const OrScene& scene,
                         const std::string& layout,
                         const std::function<std::string(int)>& view_name, const fs::path& dir) {
  write_file_atomically(dir / "gt" / "classes.yaml", classes_yaml(scene));
  write_file_atomically(dir / "vlm" / "prompt.txt", vlm_prompt());
  write_file_atomically(dir / "synth.yaml", synth_yaml(s));
  write_file_atomically(dir / "capture.yaml", capture_yaml(s, scene, layout, view_name));
}

void write_folder_atomically(const fs::path& out_dir,
                             const std::function<void(const fs::path&)>& write) {
  if (fs::exists(out_dir) && !(fs::is_directory(out_dir) && fs::is_empty(out_dir))) {
    throw std::invalid_argument(out_dir.string() + " already exists and is not an empty folder");
  }
  const fs::path parent = out_dir.has_parent_path() ? out_dir.parent_path() : fs::path(".");
  fs::create_directories(parent);
  // Unique per process and call, so concurrent generations never share a temporary folder.
  static std::atomic<unsigned> counter{0};
  const fs::path tmp = parent / (out_dir.filename().string() + ".partial-" +
                                 std::to_string(::getpid()) + "-" + std::to_string(counter++));
  fs::remove_all(tmp);
  try {
    write(tmp);
    if (fs::exists(out_dir)) fs::remove(out_dir);  // the empty folder checked above
    fs::rename(tmp, out_dir);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
}

std::vector<std::pair<std::string, std::string>> settings_entries(const OrCaptureSettings& s) {
  std::vector<std::pair<std::string, std::string>> e = {
      {"seed", std::to_string(s.scene.seed)},     {"phase", to_string(s.scene.phase)},
      {"views", std::to_string(s.scene.views)},   {"width", std::to_string(s.scene.width)},
      {"height", std::to_string(s.scene.height)}, {"preset", enum_name(s.preset, preset_names())},
  };
  for (const KnobField& k : synth_knob_table().fields())
    e.emplace_back(k.spec.name, knob_value(s.knobs, k));
  return e;
}

OrCaptureSettings make_settings(const std::vector<std::pair<std::string, std::string>>& entries) {
  OrCaptureSettings s;
  for (const auto& [name, value] : entries) {
    if (name == "preset") s.preset = parse_enum(value, preset_names(), "preset");
  }
  s.knobs = preset_knobs(s.preset);
  // Range-checked before narrowing: --width 4294967456 wrapped to 160 in an int.
  auto integer = [](const std::string& name, const std::string& value, long long max) {
    size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != value.size() || v < 0)
      throw std::invalid_argument(name + ": '" + printable(value) +
                                  "' is not a non-negative integer");
    if (v > max)
      throw std::invalid_argument(name + ": " + value + " is over the limit of " +
                                  std::to_string(max));
    return v;
  };
  constexpr long long kMaxInt = std::numeric_limits<int>::max();
  for (const auto& [name, value] : entries) {
    if (name == "preset") continue;
    if (name == "seed") {
      s.scene.seed = static_cast<uint64_t>(integer(name, value, LLONG_MAX));
    } else if (name == "phase") {
      s.scene.phase = parse_or_phase(value);
    } else if (name == "views") {
      s.scene.views = static_cast<int>(integer(name, value, kMaxInt));
    } else if (name == "width") {
      s.scene.width = static_cast<int>(integer(name, value, kMaxImagePixels));
    } else if (name == "height") {
      s.scene.height = static_cast<int>(integer(name, value, kMaxImagePixels));
    } else {
      set_knob(s.knobs, name, value);
    }
  }
  // gslift reads no image over kMaxImagePixels, so it generates none either (9000 x 9000 was
  // written; 100000 x 100000 ended in OpenCV's allocation error).
  if (s.scene.width < 1 || s.scene.height < 1 ||
      static_cast<long long>(s.scene.width) * s.scene.height > kMaxImagePixels)
    throw std::invalid_argument("width x height: " + std::to_string(s.scene.width) + " x " +
                                std::to_string(s.scene.height) + " is not from 1 x 1 to " +
                                std::to_string(kMaxImagePixels) + " pixels");
  // The scene's own limits, here too: an embedded: spec with views=2 is bad input, found
  // before the capture is generated (it was an internal error from inside the generator).
  check_or_scene_options(s.scene);
  return s;
}

std::string capture_name(const OrCaptureSettings& s) {
  return "or_s" + std::to_string(s.scene.seed) + "_" + to_string(s.scene.phase);
}

void write_or_capture(const OrCaptureSettings& s, const fs::path& out_dir) {
  OrScene scene = make_or_scene(s.scene);
  const std::set<int> draped = drape_equipment(scene, s.knobs.drapes, s.scene.seed);
  const Bvh bvh(scene.primitives);
  write_folder_atomically(out_dir, [&](const fs::path& tmp) {
    const int views = static_cast<int>(scene.cameras.size());
    const int train = views - held_out_count(views);
    const int points_per_view = s.knobs.sparse_points / std::max(1, train);
    std::vector<ViewOutput> outputs(views);
    tbb::parallel_for(0, views, [&](int i) {
      write_view(s, scene, draped, bvh, i, points_per_view, tmp, outputs[i]);
    });

    ColmapModel model;
    Camera shared = scene.cameras.front().camera;
    model.cameras[1] = shared;
    for (int i = 0; i < views; ++i) {
      const OrCamera& c = scene.cameras[i];
      RandomStream pose_rng(stream_seed(s.scene.seed, kPoseNoiseStream, i));
      Pose pose = perturb_pose(c.pose, s.knobs.pose_noise_deg, s.knobs.pose_noise_m, pose_rng);
      pose.t *= s.knobs.world_scale;
      model.images.push_back({i + 1, 1, c.name + ".png", pose});
      // Views are concatenated in view order, whatever order the threads finished in.
      const SparsePoints& p = outputs[i].points;
      model.points.xyz.insert(model.points.xyz.end(), p.xyz.begin(), p.xyz.end());
      model.points.rgb.insert(model.points.rgb.end(), p.rgb.begin(), p.rgb.end());
    }
    write_colmap_text(tmp / "sparse" / "0", model);
    // The depth PNGs hold millimetres of the room whatever the units: their scale per unit
    // says what a unit is (a 10 m room x 10 would overflow 16-bit millimetres).
    std::ostringstream layout = classic_stream();
    layout.precision(12);
    layout << "model: sparse/0\nimages: images\ndepth: {folder: depth, scale: "
           << 1000 / s.knobs.world_scale << "}\n";
    write_capture_files(
        s, scene, layout.str(), [&](int i) { return scene.cameras[i].name; }, tmp);
  });
}

}  // namespace gslift::synth
