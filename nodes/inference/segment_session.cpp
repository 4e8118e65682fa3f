#include "nodes/inference/segment_session.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "base/utf8.hpp"
#include "nodes/inference/filter_3d.hpp"
#include "nodes/inference/prompt_io.hpp"
#include "nodes/inference/query_files.hpp"
#include "nodes/inference/selection_mask.hpp"
#include "nodes/inference/selection_output.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "nodes/scene/view_poses.hpp"
#include "nodes/splat/ply_io.hpp"
#include "runtime/exit_codes.hpp"

namespace gslift {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::vector<int> requested_views(const nlohmann::json& j, const Capture& capture, const Prompt& p) {
  if (capture.find_view(p.view) < 0)
    throw InputError("the capture has no view '" + printable(p.view) + "'");
  if (!j.contains("views")) return {capture.find_view(p.view)};
  std::vector<int> views;
  if (j["views"] == "all") {
    for (size_t v = 0; v < capture.views.size(); ++v) views.push_back(static_cast<int>(v));
    return views;
  }
  if (!j["views"].is_array()) throw InputError("\"views\" must be a list of view names or \"all\"");
  for (const auto& name : j["views"]) {
    const int v = name.is_string() ? capture.find_view(name.get<std::string>()) : -1;
    if (v < 0) throw InputError("the capture has no view " + printable(name.dump()));
    views.push_back(v);
  }
  return views;
}

// The longest prompt line read: a prompt is a few hundred bytes (mask prompts name a PNG file),
// and a line read whole without a bound ended the session when it outgrew memory.
constexpr size_t kMaxPromptLine = size_t(1) << 20;

// How much of an error message a reply carries (a parse error quotes the token it stopped at).
constexpr size_t kMaxErrorBytes = 1000;

// Reads the next line of `in` (without its '\n') into `line`, keeping its first kMaxPromptLine
// bytes and skipping the rest. Returns the line's whole length, or -1 at the end of the input
// (or at a read error: the caller checks in.bad()).
int64_t read_prompt_line(std::istream& in, std::string& line) {
  line.clear();
  int64_t length = 0;
  char chunk[1 << 16];
  for (;;) {
    in.getline(chunk, sizeof chunk);
    const auto got = static_cast<size_t>(in.gcount());
    const bool ended = !in.fail() && !in.eof();  // the '\n' was read (and counted in gcount)
    const size_t stored = ended ? got - 1 : got;
    if (line.size() < kMaxPromptLine)
      line.append(chunk, std::min(stored, kMaxPromptLine - line.size()));
    length += static_cast<int64_t>(stored);
    if (ended) return length;
    if (in.eof() || in.bad()) return length > 0 ? length : -1;
    in.clear();  // the chunk filled up: the line goes on
  }
}

// Two names whose files would be one (query_file_stem: "", "." and ".." are all "query";
// "/a/x/P" and "../../a/x/p" are both "a_x_p") must not overwrite each other silently: the
// first name to write a stem into an output folder keeps it for the session.
void claim_file_stem(std::map<std::string, std::string>& owners, const std::string& dir,
                     const std::string& name) {
  const std::string key = dir + '\0' + query_file_stem(name);
  const auto [it, inserted] = owners.emplace(key, name);
  if (!inserted && it->second != name)
    throw InputError("the name \"" + printable(name) + "\" writes the same files as \"" +
                     printable(it->second) + "\" (" + query_file_stem(name) + ") in " +
                     printable(dir) + "; rename one of them");
}

}  // namespace

int run_segment_session(const GaussianModel& model, const Capture& capture,
                        const PromptOptions& options, std::istream& in, std::ostream& out) {
  PromptSegmenter segmenter(model, capture, options);
  std::map<int, std::unique_ptr<SelectionMasker>> mask_views;  // built on first use
  std::map<std::string, std::string> stem_owners;              // claim_file_stem
  int answered = 0;
  std::string text;
  int line = 1;
  for (int64_t length; (length = read_prompt_line(in, text)) >= 0; ++line) {
    if (static_cast<size_t>(length) <= kMaxPromptLine &&
        text.find_first_not_of(" \t\r") == std::string::npos)
      continue;
    nlohmann::json reply;
    try {
      if (static_cast<size_t>(length) > kMaxPromptLine)
        throw InputError("the line is " + std::to_string(length) + " bytes long, over the " +
                         std::to_string(kMaxPromptLine) + "-byte limit of a prompt; skipped");
      nlohmann::json j;
      try {
        j = parse_json(text);
      } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("not JSON: ") + e.what());
      }
      const Prompt p = prompt_from_json(j, ".", "prompt", static_cast<size_t>(line),
                                        {"output", "ply", "views", "filter"});
      const std::vector<int> views = requested_views(j, capture, p);
      const int pv = capture.find_view(p.view);
      if (pv >= 0) segmenter.feature_map(pv);  // once per view, not part of a prompt's latency
      for (int v : views)
        if (!mask_views.count(v))
          mask_views[v] = std::make_unique<SelectionMasker>(model, capture.views[v].camera,
                                                            capture.views[v].pose);
      const auto t0 = Clock::now();
      const PromptSelection s = segmenter.select(p);
      std::vector<uint8_t> indicator = s.selected;
      if (j.value("filter", false)) {
        std::vector<int32_t> ids(s.selected.size());
        for (size_t g = 0; g < ids.size(); ++g) ids[g] = s.selected[g] ? 0 : -1;
        const Filter3dResult f = filter_instances_3d(model.means, ids, Filter3dOptions{},
                                                     model.features, model.feature_dim);
        for (size_t g = 0; g < ids.size(); ++g) indicator[g] = f.instance_ids[g] == 0;
      }
      const double select_ms = ms_since(t0);
      const auto t1 = Clock::now();
      MaskSet masks;
      for (int v : views) {
        Mask m;
        m.pixels = mask_views[v]->mask(indicator, 0.5f);
        m.label = p.name;
        masks.views.push_back({capture.views[v].name, {std::move(m)}});
      }
      const double mask_ms = ms_since(t1);
      int64_t selected = 0;
      for (uint8_t x : indicator) selected += x;
      reply = {{"ok", true},           {"name", p.name},
               {"selected", selected}, {"select_ms", select_ms},
               {"mask_ms", mask_ms},   {"latency_ms", select_ms + mask_ms}};
      nlohmann::json names = nlohmann::json::array();
      for (const ViewMasks& vm : masks.views) names.push_back(vm.view);
      reply["views"] = names;
      if (j.contains("output")) {
        const std::filesystem::path dir = j["output"].get<std::string>();
        std::filesystem::create_directories(dir);
        claim_file_stem(stem_owners, std::filesystem::weakly_canonical(dir).string(), p.name);
        if (j.value("ply", false)) {
          GaussianModel labelled = model;
          labelled.instance_ids.assign(model.size(), -1);
          for (size_t g = 0; g < model.size(); ++g)
            if (indicator[g]) labelled.instance_ids[g] = 0;
          write_selection_files(masks, labelled, {p.name}, capture, dir);
        } else {
          for (const ViewMasks& vm : masks.views) {
            const int vi = capture.find_view(vm.view);
            const cv::Mat rgb =
                capture.views[vi].rgb.present() ? capture.views[vi].rgb.load() : cv::Mat();
            write_mask_files(dir, vm.view + "__" + query_file_stem(p.name), vm.masks[0].pixels, rgb,
                             p.name);
          }
        }
        reply["output"] = dir.string();
      }
      ++answered;
    } catch (const std::exception& e) {
      // Printable: a message may quote the line's bytes, and a reply must stay valid UTF-8.
      reply = {{"ok", false}, {"line", line}, {"error", printable(e.what(), kMaxErrorBytes)}};
    }
    out << reply.dump() << std::endl;
  }
  if (in.bad())
    throw InputError("reading the prompts failed after line " + std::to_string(line - 1));
  return answered;
}

// The value of a numeric option, which must be all of `text` and finite (std::stod took "nan",
// "1e308" and "0.5abc"); std::invalid_argument (a usage error) otherwise.
double option_number(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    throw std::invalid_argument(option + " takes a number, not '" + printable(text) + "'");
  return v;
}

int segment_main(int argc, char** argv) {
  std::string model_path, input, poses;
  PromptOptions options;
  CaptureOptions capture_options;
  capture_options.skip_missing_images = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout
          << "usage: gslift segment MODEL.ply --input CAPTURE [--poses FILE] [--tau T]\n"
             "                      [--adaptive] [--downscale N]\n\n"
             "Loads a model with affinity features (features.correspondence) and a capture\n"
             "once, then reads one JSON prompt per stdin line and prints one JSON reply per\n"
             "prompt (docs/saga.md, nodes/inference/segment_session.hpp). --poses: the poses\n"
             "the model was trained at (a run's recon/refined_poses.txt), in place of the\n"
             "capture's.\n";
      return exit_code::kOk;
    }
    if (arg == "--adaptive") {
      options.threshold = PromptThreshold::Adaptive;
      continue;
    }
    if (arg.rfind("--", 0) == 0) {
      if (i + 1 >= argc) {
        std::cerr << "gslift segment: " << arg << " needs a value\n";
        return exit_code::kUsage;
      }
      const std::string value = argv[++i];
      try {
        if (arg == "--input")
          input = value;
        else if (arg == "--poses")
          poses = value;
        else if (arg == "--tau") {
          // A threshold on a cosine similarity: 1 or more selects nothing, 0 or less everything.
          options.tau = option_number(arg, value);
          if (!(options.tau > 0 && options.tau < 1))
            throw std::invalid_argument("--tau must lie between 0 and 1 (exclusive), not " +
                                        printable(value));
        } else if (arg == "--downscale") {
          const double d = option_number(arg, value);
          if (d != std::floor(d) || d < 1 || d > kMaxDownscale)
            throw std::invalid_argument("--downscale must be a whole number from 1 to " +
                                        std::to_string(kMaxDownscale) + ", not " +
                                        printable(value));
          capture_options.downscale = static_cast<int>(d);
        } else
          throw std::invalid_argument("unknown option " + arg);
      } catch (const std::exception& e) {
        std::cerr << "gslift segment: " << e.what() << " (see gslift segment --help)\n";
        return exit_code::kUsage;
      }
      continue;
    }
    model_path = arg;
  }
  if (model_path.empty() || input.empty()) {
    std::cerr << "gslift segment: MODEL.ply and --input CAPTURE are required\n";
    return exit_code::kUsage;
  }
  try {
    const GaussianModel model = read_ply(model_path);
    Capture capture = load_capture(resolve_capture_path(input), capture_options);
    if (!poses.empty()) apply_view_poses(capture, read_view_poses(poses), poses);
    run_segment_session(model, capture, options, std::cin, std::cout);
    // std::cin reads through stdio: a read error (stdin a folder, an I/O error) ends its lines
    // like the end of the input does, and only ferror tells the two apart.
    if (std::ferror(stdin))
      throw InputError(std::string("reading the prompts from stdin failed: ") +
                       std::strerror(errno));
  } catch (const InputError& e) {
    std::cerr << "gslift segment: " << e.what() << "\n";
    return exit_code::kBadInput;
  }
  return exit_code::kOk;
}

}  // namespace gslift
