// gslift view's speed on a run folder (default out/langor, the main job): the frame the page asks
// for at 640x480 (gslift's rasterizer + JPEG encoding) from the first capture camera and from
// orbit poses around it, in colour and instance colours, a click's latency (a SAGA point
// prompt on the model's features, ViewSession::prompt) alone and with the highlighted frame that
// follows, and a LangOR text query's (the instances chosen and their mask in a held-out view), at
// 1 and 2 threads; medians of `reps` rounds. A click's selection is also scored
// against the ground truth of the clicked class in the first view (IoU), per threshold.
// Writes DIR/viewer.json and DIR/viewer.svg (default bench/results).
//
//   bench_viewer [RUN_FOLDER] [DIR] [--reps R]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "base/atomic_file.hpp"
#include "base/svg.hpp"
#include "nodes/builtin.hpp"
#include "nodes/inference/prompt_segmentation.hpp"
#include "runtime/allocator.hpp"
#include "runtime/registry.hpp"
#include "viewer/view_session.hpp"

using namespace gslift;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

std::string machine() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = -1;
  in >> load;
  return load;
}

// Camera 0 turned by `degrees` about its own up axis through the point `distance` ahead.
Pose orbit(const Pose& p, double degrees, double distance) {
  const Eigen::Vector3d up = -p.R.row(1).transpose(), ahead = p.R.row(2).transpose();
  const Eigen::Vector3d pivot = p.centre() + distance * ahead;
  const Eigen::Matrix3d q = Eigen::AngleAxisd(degrees * M_PI / 180, up).toRotationMatrix();
  Pose out;
  out.R = p.R * q.transpose();
  out.t = -out.R * (pivot + q * (p.centre() - pivot));
  return out;
}

double iou(const cv::Mat1b& a, const cv::Mat1b& b) {
  const double inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
  return uni > 0 ? inter / uni : 0;
}

struct Timing {
  int threads = 0;
  double colour_frame_ms = 0, instance_frame_ms = 0, prompt_ms = 0, prompt_and_frame_ms = 0,
         text_query_ms = 0;
};

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_in_process();
  Registry registry;
  register_builtin_nodes(registry);  // the embedded capture provider
  std::string run = std::string(GSLIFT_SOURCE_DIR) + "/out/langor";
  std::string out_dir = std::string(GSLIFT_SOURCE_DIR) + "/bench/results";
  int reps = 5, positional = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc)
      reps = std::max(1, std::stoi(argv[++i]));
    else
      (positional++ == 0 ? run : out_dir) = a;
  }
  ViewSession session(open_run_folder(run));
  const Capture& capture = session.scene().capture;
  const View& first = capture.views.at(0);
  const Camera camera = first.camera.scaled(640.0 / first.camera.width);
  // Orbit about the model's mean, as the page does.
  const GaussianModel& model = session.scene().model;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t g = 0; g < model.size(); ++g)
    mean += Eigen::Vector3d(model.means[3 * g], model.means[3 * g + 1], model.means[3 * g + 2]);
  mean /= static_cast<double>(model.size());
  const double distance = (mean - first.pose.centre()).dot(first.pose.R.row(2).transpose());
  std::vector<Pose> poses;
  for (int k = -4; k <= 4; ++k) poses.push_back(orbit(first.pose, 5.0 * k, distance));

  // Clicks: the innermost pixel of each ground-truth class in the first view.
  MaskSet gt;
  gt.views.push_back({first.name, {}});
  const cv::Mat semantic = first.gt_semantic.load();
  std::map<std::string, cv::Mat1b> class_masks;
  for (const auto& [id, name] : capture.classes) {
    if (id == 0) continue;
    cv::Mat1b m = semantic == id;
    if (cv::countNonZero(m) < 200) continue;  // a sliver: no object to click on
    class_masks[name] = m;
    Mask mask;
    mask.pixels = m;
    mask.label = name;
    gt.views[0].masks.push_back(mask);
  }
  const PromptSet clicks = prompts_from_masks(gt, first.name, PromptKind::Point);
  const int held_out = capture.test_views().at(0);
  std::printf("%s: %zu Gaussians, %zu clicks in %s\n", run.c_str(), session.scene().model.size(),
              clicks.prompts.size(), first.name.c_str());

  std::vector<Timing> timings;
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Timing t;
    t.threads = threads;
    std::vector<double> colour, instances, prompt, prompt_frame, text_query;
    session.frame({camera, first.pose, FrameMode::Colour, {}});  // warm: the display model
    if (session.scene().encoder)  // warm: the held-out view's masker, the encoder's words
      for (const auto& [name, mask] : class_masks)
        session.query(name), session.selection_mask(held_out);
    for (int r = 0; r < reps; ++r) {
      session.clear_selection();
      for (FrameMode mode : {FrameMode::Colour, FrameMode::Instances})
        for (const Pose& pose : poses) {
          const auto t0 = Clock::now();
          const cv::Mat3b frame = session.frame({camera, pose, mode, {}});
          std::vector<uchar> jpeg;
          cv::imencode(".jpg", frame, jpeg, {cv::IMWRITE_JPEG_QUALITY, 90});
          (mode == FrameMode::Colour ? colour : instances).push_back(ms_since(t0));
        }
      for (const Prompt& p : clicks.prompts) {
        const auto t0 = Clock::now();
        prompt.push_back(session.prompt(p, camera, first.pose, 0.75).latency_ms);
        const cv::Mat3b frame = session.frame({camera, first.pose, FrameMode::Colour, {}});
        std::vector<uchar> jpeg;
        cv::imencode(".jpg", frame, jpeg, {cv::IMWRITE_JPEG_QUALITY, 90});
        prompt_frame.push_back(ms_since(t0));
      }
      // A LangOR text query per class name: the instances chosen and their mask in the held-out
      // view (the view's masker is built on the first query, as the page does, and kept).
      if (session.scene().encoder)
        for (const auto& [name, mask] : class_masks) {
          const auto t0 = Clock::now();
          session.query(name);
          const cv::Mat1b selected = session.selection_mask(held_out);
          text_query.push_back(ms_since(t0));
          if (selected.empty()) std::abort();  // keeps the mask observable
        }
    }
    t.colour_frame_ms = median(colour);
    t.instance_frame_ms = median(instances);
    t.prompt_ms = median(prompt);
    t.prompt_and_frame_ms = median(prompt_frame);
    t.text_query_ms = median(text_query);
    std::printf(
        "threads %d: frame %.1f ms (%.1f frames/s), instances %.1f ms, click %.1f ms, click + "
        "highlighted frame %.1f ms, text query + held-out mask %.2f ms\n",
        threads, t.colour_frame_ms, 1000 / t.colour_frame_ms, t.instance_frame_ms, t.prompt_ms,
        t.prompt_and_frame_ms, t.text_query_ms);
    std::fflush(stdout);
    timings.push_back(t);
  }

  // What a click selects, against the clicked class's ground truth in the first view.
  nlohmann::json clicks_json = nlohmann::json::array();
  for (double tau : {0.5, 0.75, 0.9}) {
    std::vector<double> ious;
    nlohmann::json per_class;
    for (const Prompt& p : clicks.prompts) {
      session.prompt(p, camera, first.pose, tau);
      const double v = iou(session.selection_mask(0), class_masks.at(p.name));
      per_class[p.name] = v;
      ious.push_back(v);
    }
    double mean = 0;
    for (double v : ious) mean += v / ious.size();
    std::printf("tau %.2f: mean click IoU %.3f\n", tau, mean);
    clicks_json.push_back({{"tau", tau}, {"mean_iou", mean}, {"iou", per_class}});
  }

  nlohmann::json j;
  j["benchmark"] = "viewer";
  j["run"] = run;
  j["gaussians"] = session.scene().model.size();
  j["frame"] = {camera.width, camera.height};
  j["frame_timed"] = "ViewSession::frame (rasterizer, RGB) + JPEG encoding, 9 orbit poses";
  j["click_timed"] = "ViewSession::prompt (sparse feature render + scoring); then + the frame";
  j["text_query_timed"] =
      "ViewSession::query (a class name) + selection_mask of the first held-out view, one "
      "untimed pass first";
  j["repetitions"] = reps;
  j["machine"] = machine();
  j["hardware_threads"] = std::thread::hardware_concurrency();
  j["load_average_1min_at_end"] = load_average();
  for (const Timing& t : timings)
    j["rows"].push_back({{"threads", t.threads},
                         {"colour_frame_ms", t.colour_frame_ms},
                         {"colour_frames_per_s", 1000 / t.colour_frame_ms},
                         {"instance_frame_ms", t.instance_frame_ms},
                         {"click_ms", t.prompt_ms},
                         {"click_and_frame_ms", t.prompt_and_frame_ms},
                         {"text_query_ms", t.text_query_ms}});
  j["click_iou_first_view"] = clicks_json;
  write_file_atomically(out_dir + "/viewer.json", j.dump(2) + "\n");

  // Bars per measure, 1 and 2 threads side by side, the 100 ms line (10 frames/s and the click
  // floor alike).
  const int W = 640, H = 360, L = 60, B = 70, T = 50;
  double max_ms = 120;
  for (const Timing& t : timings)
    max_ms = std::max({max_ms, t.colour_frame_ms, t.instance_frame_ms, t.prompt_and_frame_ms});
  auto py = [&](double ms) { return H - B - (H - T - B) * ms / max_ms; };
  Svg svg(W, H, 12, true);
  svg.text(W / 2, 18,
           "gslift view, 640x480, " + std::to_string(session.scene().model.size()) +
               " Gaussians: median ms (lower is better)",
           "text-anchor='middle' font-size='14'");
  svg.text(W / 2, 36, machine() + ", load " + std::to_string(load_average()).substr(0, 4),
           "text-anchor='middle' font-size='11'");
  svg.line(L, H - B, W - 10, H - B, "black");
  svg.line(L, py(100), W - 10, py(100), "#d62728", "stroke-dasharray='5,4'");
  svg.text(W - 12, py(100) - 4, "100 ms (10 frames/s; click floor)",
           "text-anchor='end' fill='#d62728'");
  const char* names[] = {"frame (colour)", "frame (instances)", "click", "click + frame"};
  const char* colours[] = {"#9ecae1", "#1f77b4"};
  for (int m = 0; m < 4; ++m)
    for (size_t k = 0; k < timings.size(); ++k) {
      const Timing& t = timings[k];
      const double v[] = {t.colour_frame_ms, t.instance_frame_ms, t.prompt_ms,
                          t.prompt_and_frame_ms};
      const double x = L + 20 + m * 140 + k * 50;
      svg.rect(x, py(v[m]), 44, H - B - py(v[m]), colours[k]);
      char label[32];
      std::snprintf(label, sizeof label, "%.0f", v[m]);
      svg.text(x + 22, py(v[m]) - 4, label, "text-anchor='middle'");
    }
  for (int m = 0; m < 4; ++m)
    svg.text(L + 20 + m * 140 + 47, H - B + 18, names[m], "text-anchor='middle'");
  for (size_t k = 0; k < timings.size(); ++k) {
    svg.rect(L + 20 + k * 110, H - 30, 12, 12, colours[k]);
    svg.text(L + 36 + k * 110, H - 20, std::to_string(timings[k].threads) + " thread(s)");
  }
  write_file_atomically(out_dir + "/viewer.svg", svg.str());
  std::printf("wrote %s/viewer.{json,svg}\n", out_dir.c_str());
  return 0;
}
