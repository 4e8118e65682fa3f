#include "nodes/vlm/register.hpp"

#include <cstdlib>
#include <filesystem>

#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "nodes/boxes/context_prompt.hpp"
#include "nodes/ingest/vlm_reply.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/vlm/query_vlm.hpp"
#include "runtime/atomic_file.hpp"

namespace gslift {
namespace {

// The view's image exactly as the capture holds it (after any ingest downscale), so `pixels`
// coordinates need no rescaling.
std::string encode_png(const View& view) {
  const cv::Mat rgb = view.rgb.load();
  cv::Mat bgr;
  if (rgb.channels() == 3)
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  else
    bgr = rgb;
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", bgr, bytes))
    throw InputError("vlm.query: view '" + view.name + "': its image cannot be encoded as PNG");
  return std::string(bytes.begin(), bytes.end());
}

// Where vlm/prompt.txt and vlm/<view>/round_<k>.txt go: the node's output folder, or with
// into_capture the folder the capture was read from (a capture built in memory has none, so its
// replies stay in the output folder), which turns the live run into a capture ingest.vlm can
// replay.
std::filesystem::path reply_root(NodeContext& ctx, const Capture& capture) {
  if (ctx.param_bool("into_capture")) {
    if (!capture.root.empty()) return capture.root;
    spdlog::warn(
        "vlm.query: into_capture: capture '{}' has no folder; replies go to the node's "
        "output folder",
        capture.name);
  }
  return ctx.out_dir();
}

std::string round_name(int k) {
  return "round_" + std::to_string(k) + ".txt";
}

}  // namespace

void register_vlm_nodes(Registry& registry) {
  const VlmQueryOptions d;
  NodeSpec spec{
      "vlm.query",
      "ask a live OpenAI-compatible VLM server for grounding boxes, several rounds per view; "
      "stores the raw replies and parses them like ingest.vlm",
      {{"capture", PortTypeName<Capture>::value, "the views to show the VLM"},
       {"prompt", PortTypeName<Vocabulary>::value, "the grounding prompt (boxes.prompt)"}},
      {{"boxes", PortTypeName<BoxSet>::value,
        "every round's boxes per view, XYXY pixels, with round and reply position (as "
        "ingest.vlm)"}},
      {required_string_param("url",
                             "chat-completions endpoint, e.g. "
                             "http://127.0.0.1:8000/v1/chat/completions"),
       string_param("model", "", "served model name sent in the request"),
       int_param("rounds", d.rounds, "requests per view (LangOR: 5)", 1, 100),
       float_param("temperature", d.temperature, "sampling temperature; > 0 so rounds differ", 0,
                   2),
       int_param("max_tokens", d.max_tokens, "reply length limit", 16),
       float_param("timeout_s", d.timeout_s, "per-request time limit, connect included", 0.01),
       int_param("retries", d.retries,
                 "extra attempts after a timeout, refused connection, 429 or 5xx", 0, 20),
       float_param("backoff_s", d.backoff_s, "sleep before retry k: backoff_s x 2^(k-1)", 0),
       int_param("concurrency", d.concurrency, "requests in flight at once", 1, 64),
       string_param("views", "all", "views to ask about", {"train", "test", "all"}),
       string_param("api_key_env", "",
                    "environment variable holding a bearer token (never put a key in the YAML)"),
       string_param("coords", "norm1000", "the VLM's box coordinate space (see ingest.vlm)",
                    {"norm1000", "resized_abs", "pixels"}),
       int_param("input_width", 0, "resized_abs: the model's input width", 0),
       int_param("input_height", 0, "resized_abs: the model's input height", 0),
       bool_param("into_capture", false,
                  "write the raw replies into the capture's own vlm/ folder (overwriting what is "
                  "there) instead of the node's output folder")}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    const Capture& capture = *ctx.input<Capture>("capture");
    const Vocabulary& vocabulary = *ctx.input<Vocabulary>("prompt");
    VlmQueryOptions o;
    o.url = ctx.param_string("url");
    o.model = ctx.param_string("model");
    o.rounds = static_cast<int>(ctx.param_int("rounds"));
    o.temperature = ctx.param_float("temperature");
    o.max_tokens = static_cast<int>(ctx.param_int("max_tokens"));
    o.timeout_s = ctx.param_float("timeout_s");
    o.retries = static_cast<int>(ctx.param_int("retries"));
    o.backoff_s = ctx.param_float("backoff_s");
    o.concurrency = static_cast<int>(ctx.param_int("concurrency"));
    o.seed = ctx.seed();
    const std::string& key_env = ctx.param_string("api_key_env");
    if (!key_env.empty()) {
      const char* key = std::getenv(key_env.c_str());
      if (!key || !*key)
        throw InputError("vlm.query: environment variable " + key_env +
                         " (param api_key_env) is not set");
      o.api_key = key;
    }
    VlmFrame frame;
    frame.coords = vlm_coords_from_string(ctx.param_string("coords"));
    frame.input_width = static_cast<int>(ctx.param_int("input_width"));
    frame.input_height = static_cast<int>(ctx.param_int("input_height"));
    if (frame.coords == VlmCoords::ResizedAbs &&
        (frame.input_width <= 0 || frame.input_height <= 0))
      throw InputError("vlm.query: coords resized_abs needs input_width and input_height");

    const std::vector<int> views = capture.views_named(ctx.param_string("views"));
    std::vector<VlmImage> images;
    for (int v : views) images.push_back({capture.views[v].name, encode_png(capture.views[v])});
    const auto replies = query_vlm(images, vocabulary.prompt, o, [&] { return ctx.cancelled(); });
    ctx.check_cancelled();

    // Raw replies in the capture layout (docs/capture_format.md), so the folder can serve as a
    // capture's vlm/ for ingest.vlm later, without a server.
    const std::filesystem::path dir = reply_root(ctx, capture);
    if (!dir.empty()) write_file_atomically(dir / "vlm" / "prompt.txt", vocabulary.prompt);
    BoxSet boxes;
    for (const View& v : capture.views) boxes.views.push_back({v.name, 0, {}});
    size_t unparsed = 0, retried = 0, count = 0;
    for (size_t i = 0; i < views.size(); ++i) {
      const View& view = capture.views[views[i]];
      frame.image_width = view.camera.width;
      frame.image_height = view.camera.height;
      std::vector<std::string> contents;
      for (int k = 0; k < o.rounds; ++k) {
        const VlmRoundReply& reply = replies[i][k];
        retried += reply.attempts > 1;
        contents.push_back(reply.content);
        if (!dir.empty())
          write_file_atomically(dir / "vlm" / view.name / round_name(k), reply.content);
      }
      ViewReplies parsed = parse_view_replies(
          view.name, contents, frame, [&](int k) { return view.name + "/" + round_name(k); });
      unparsed += parsed.unparsed;
      count += parsed.boxes.boxes.size();
      boxes.views[views[i]] = std::move(parsed.boxes);
    }
    ctx.record("boxes", static_cast<double>(count));
    ctx.record("requests", static_cast<double>(views.size() * o.rounds));
    ctx.record("rounds_unparsed", static_cast<double>(unparsed));
    ctx.record("requests_retried", static_cast<double>(retried));
    ctx.output("boxes", std::move(boxes));
  });
}

}  // namespace gslift
