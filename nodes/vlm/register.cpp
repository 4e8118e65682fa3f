#include "nodes/vlm/register.hpp"

#include <filesystem>
#include <memory>

#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "base/atomic_file.hpp"
#include "base/http_post.hpp"
#include "nodes/ingest/vlm_reply.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/vocabulary.hpp"
#include "nodes/vlm/label_mapping.hpp"
#include "nodes/vlm/query_vlm.hpp"

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

// vlm.query's params: the request's, then which views, the key, the coordinate frame and where
// the raw replies go.
struct VlmQueryParams {
  VlmQueryOptions query;
  ViewSet views = ViewSet::All;
  std::string api_key_env;
  VlmCoords coords = VlmCoords::Norm1000;
  int input_width = 0, input_height = 0;  // resized_abs: the model's input size
  bool into_capture = false;
};

const ParamTable<VlmQueryParams>& vlm_query_node_param_table() {
  using P = VlmQueryParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .nest(&P::query, vlm_query_param_table())
          .add("views", &P::views, view_set_names(), "views to ask about")
          .add("api_key_env", &P::api_key_env,
               "environment variable holding a bearer token (never put a key in the YAML)")
          .add("coords", &P::coords, vlm_coords_names(),
               "the VLM's box coordinate space (see ingest.vlm)")
          .add("input_width", &P::input_width, "resized_abs: the model's input width", 0)
          .add("input_height", &P::input_height, "resized_abs: the model's input height", 0)
          .add("into_capture", &P::into_capture,
               "write the raw replies into the capture's own vlm/ folder (overwriting what is "
               "there) instead of the node's output folder");
  return table;
}

// Where vlm/prompt.txt and vlm/<view>/round_<k>.txt go: the node's output folder, or with
// into_capture the folder the capture was read from (a capture built in memory has none, so its
// replies stay in the output folder), which turns the live run into a capture ingest.vlm can
// replay.
std::filesystem::path reply_root(NodeContext& ctx, const Capture& capture, bool into_capture) {
  if (into_capture) {
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

void map_labels(NodeContext& ctx, const Vocabulary& vocabulary, BoxSet& boxes,
                const UnwiredLabelEncoder& unwired_encoder) {
  std::shared_ptr<const TextEncoder> encoder;
  if (ctx.has_input("encoder"))
    encoder = ctx.input<TextEncoder>("encoder");
  else
    encoder = unwired_encoder(vocabulary);
  const LabelMappingReport mapping =
      map_box_labels(boxes, VocabularyMatcher(*encoder, vocabulary.class_names()));
  std::string mapped, unmapped;
  for (const auto& m : mapping.mapped) mapped += (mapped.empty() ? "" : "; ") + m;
  for (const auto& m : mapping.unmapped) {
    unmapped += (unmapped.empty() ? "" : "; ") + m;
    spdlog::warn("vlm.query: label kept as its own class: {}", m);
  }
  if (!mapped.empty()) ctx.record("labels_mapped", mapped);
  if (!unmapped.empty()) ctx.record("labels_unmapped", unmapped);
}

void run_vlm_query(NodeContext& ctx, VlmQueryParams p, const UnwiredLabelEncoder& unwired_encoder) {
  const Capture& capture = *ctx.input<Capture>("capture");
  const Vocabulary& vocabulary = *ctx.input<Vocabulary>("prompt");
  VlmQueryOptions& o = p.query;
  o.seed = ctx.seed();
  o.api_key = api_key_from_env("vlm.query", p.api_key_env);
  VlmFrame frame;
  frame.coords = p.coords;
  frame.input_width = p.input_width;
  frame.input_height = p.input_height;
  if (frame.coords == VlmCoords::ResizedAbs && (frame.input_width <= 0 || frame.input_height <= 0))
    throw InputError("vlm.query: coords resized_abs needs input_width and input_height");

  const std::vector<int> views = capture.views_named(p.views);
  std::vector<VlmImage> images;
  for (int v : views) images.push_back({capture.views[v].name, encode_png(capture.views[v])});
  const auto replies = query_vlm(images, vocabulary.prompt, o, [&] { return ctx.cancelled(); });
  ctx.check_cancelled();

  // Raw replies in the capture layout (docs/capture_format.md), so the folder can serve as a
  // capture's vlm/ for ingest.vlm later, without a server.
  const std::filesystem::path dir = reply_root(ctx, capture, p.into_capture);
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
    ViewReplies parsed = parse_view_replies(view.name, contents, frame,
                                            [&](int k) { return view.name + "/" + round_name(k); });
    unparsed += parsed.unparsed;
    count += parsed.boxes.boxes.size();
    boxes.views[views[i]] = std::move(parsed.boxes);
  }
  // Free labels onto the vocabulary, through the wired encoder or the offline lexical one (a
  // prompt without classes has nothing to map onto).
  if (!vocabulary.entities.empty()) map_labels(ctx, vocabulary, boxes, unwired_encoder);
  ctx.record("boxes", static_cast<double>(count));
  ctx.record("requests", static_cast<double>(views.size() * o.rounds));
  ctx.record("rounds_unparsed", static_cast<double>(unparsed));
  ctx.record("requests_retried", static_cast<double>(retried));
  ctx.output("boxes", std::move(boxes));
}

}  // namespace

void register_vlm_nodes(Registry& registry, UnwiredLabelEncoder unwired_encoder) {
  NodeSpec spec{
      "vlm.query",
      "ask a live OpenAI-compatible VLM server for grounding boxes, several rounds per view; "
      "stores the raw replies and parses them like ingest.vlm",
      {{"capture",
        PortTypeName<Capture>::value,
        "the views to show the VLM",
        false,
        {{CaptureItem::Images}}},
       {"prompt", PortTypeName<Vocabulary>::value, "the grounding prompt (boxes.prompt)"},
       {"encoder", PortTypeName<TextEncoder>::value,
        "maps labels outside the vocabulary onto it; unwired: the lexical encoder over the "
        "prompt's vocabulary",
        true}},
      {{"boxes", PortTypeName<BoxSet>::value,
        "every round's boxes per view, XYXY pixels, with round and reply position (as "
        "ingest.vlm)"}}};
  // A live server's answers are not a function of the request: asked again, it may answer
  // otherwise (and the replies it wrote are the record of what it said), so it is never cached.
  spec.cacheable = false;
  registry.add(std::move(spec), vlm_query_node_param_table(),
               [unwired_encoder = std::move(unwired_encoder)](NodeContext& ctx, VlmQueryParams p) {
                 run_vlm_query(ctx, std::move(p), unwired_encoder);
               });
}

}  // namespace gslift
