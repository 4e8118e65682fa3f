// The fuzz targets (docs/security.md): one function per parser of untrusted input, shared by the
// libFuzzer executables (fuzz_main.cpp) and the regression test that replays every input the
// fuzzers ever crashed on (tests/data/fuzz_regressions/<target>/,
// tests/ingest/fuzz_regressions_test.cpp).
#include "fuzz/targets.hpp"

#include <map>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "fuzz/fuzz_support.hpp"
#include "graph/loader.hpp"
#include "nodes/ingest/capture_manifest.hpp"
#include "nodes/ingest/colmap_model.hpp"
#include "nodes/ingest/nerf_transforms.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/ingest/vlm_reply.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/splat/ply_io.hpp"
#include "tests/runtime/debug_nodes.hpp"

namespace gslift::fuzz {
namespace {

// Graph YAML: parsing, `extends` (the input may extend the files of tests/data/graphs/variants,
// whose folder is its base), ${} substitution with a command-line var and a --set override, and
// validation against the debug node catalogue. Every problem must be a diagnostic: no exception
// may escape load_graph_text.
void graph_yaml(const char* data, size_t size) {
  static const Registry registry = test::debug_registry();
  LoadOptions options;
  options.vars["input"] = "embedded:or";
  options.sets = {"a.value=2"};
  load_graph_text(std::string(data, size), "fuzz.yaml", registry, options, GSLIFT_FUZZ_GRAPH_DIR);
}

// capture.yaml (gslift.capture/v1 manifest).
void capture_yaml(const char* data, size_t size) {
  const auto dir = scratch() / "capture";
  write_file(dir / "capture.yaml", std::string(data, size));
  expect_input_error_only([&] { read_capture_manifest(dir); });
}

// COLMAP text model: cameras.txt, images.txt and points3D.txt, one input cut into the three
// (fuzz_support.hpp kSplit).
void colmap_text(const char* data, size_t size) {
  const auto parts = split_input(std::string(data, size), 3);
  const auto dir = scratch() / "colmap_text";
  write_file(dir / "cameras.txt", parts[0]);
  write_file(dir / "images.txt", parts[1]);
  write_file(dir / "points3D.txt", parts[2]);
  expect_input_error_only([&] { read_colmap_text(dir); });
}

// COLMAP binary model: cameras.bin, images.bin and points3D.bin, one input cut into the three
// (fuzz_support.hpp kSplit).
void colmap_binary(const char* data, size_t size) {
  const auto parts = split_input(std::string(data, size), 3);
  const auto dir = scratch() / "colmap_binary";
  write_file(dir / "cameras.bin", parts[0]);
  write_file(dir / "images.bin", parts[1]);
  write_file(dir / "points3D.bin", parts[2]);
  expect_input_error_only([&] { read_colmap_binary(dir); });
}

// NeRF transforms.json, in a folder that holds one 8 x 6 image (images/r_0.png, written once) so
// that frames naming it reach the camera and pose checks.
void transforms_json(const char* data, size_t size) {
  const auto dir = scratch() / "nerf";
  static const bool image = [&] {
    std::filesystem::create_directories(dir / "images");
    return cv::imwrite((dir / "images/r_0.png").string(),
                       cv::Mat(6, 8, CV_8UC3, cv::Scalar(1, 2, 3)));
  }();
  (void)image;
  const auto file = write_file(dir / "transforms.json", std::string(data, size));
  expect_input_error_only([&] { read_nerf_transforms(file); });
}

// Qwen-VL grounding replies: one reply parsed in each coordinate space, and as the rounds of one
// view (the input cut in two, kSplit).
void vlm_reply(const char* data, size_t size) {
  const std::string text(data, size);
  VlmFrame frame;
  frame.image_width = 64;
  frame.image_height = 48;
  frame.input_width = 32;
  frame.input_height = 24;
  for (VlmCoords c : {VlmCoords::Norm1000, VlmCoords::ResizedAbs, VlmCoords::Pixels}) {
    frame.coords = c;
    expect_input_error_only([&] { parse_vlm_reply(text, frame, 0, "reply.txt"); });
  }
  frame.coords = VlmCoords::Norm1000;
  expect_input_error_only([&] {
    parse_view_replies("v", split_input(text, 2), frame,
                       [](int k) { return "round_" + std::to_string(k) + ".txt"; });
  });
}

// COCO RLE JSON as SAM writes it: automatic mask lists and box mask lists (records or bare RLEs,
// nulls allowed).
void coco_rle(const char* data, size_t size) {
  const std::string text(data, size);
  expect_input_error_only([&] { parse_sam_auto_masks(text, "sam_auto.json"); });
  expect_input_error_only([&] { parse_sam_box_masks(text, "round_0.json"); });
}

// Mask and label PNGs: read as a label map (16-bit ids, 8-bit accepted) and as RGB.
void mask_png(const char* data, size_t size) {
  const auto file = write_file(scratch() / "mask.png", std::string(data, size));
  expect_input_error_only([&] { read_label_map(file, true); });
  expect_input_error_only([&] { read_rgb(file); });
}

// Depth priors and float maps: 16-bit PNG or float32 TIFF. The first byte picks the file
// extension (OpenCV chooses the decoder from the content, but the name is what users have).
void depth_image(const char* data, size_t size) {
  if (size == 0) return;
  const char* ext = data[0] % 2 ? ".tiff" : ".png";
  const auto file =
      write_file(scratch() / (std::string("depth") + ext), std::string(data + 1, size - 1));
  expect_input_error_only([&] { read_depth(file, 1000); });
  expect_input_error_only([&] { read_float_tiff(file); });
}

// Gaussian model PLY (INRIA layout, binary or ASCII), as splat.load reads it.
void ply(const char* data, size_t size) {
  const auto file = write_file(scratch() / "model.ply", std::string(data, size));
  expect_input_error_only([&] { read_ply(file); });
}

}  // namespace

const std::vector<std::string>& target_names() {
  static const std::vector<std::string> names = {
      "graph_yaml", "capture_yaml", "colmap_text", "colmap_binary", "transforms_json",
      "vlm_reply",  "coco_rle",     "mask_png",    "depth_image",   "ply"};
  return names;
}

void run_target(const std::string& target, const std::string& bytes) {
  static const std::map<std::string, void (*)(const char*, size_t)> targets = {
      {"graph_yaml", graph_yaml},
      {"capture_yaml", capture_yaml},
      {"colmap_text", colmap_text},
      {"colmap_binary", colmap_binary},
      {"transforms_json", transforms_json},
      {"vlm_reply", vlm_reply},
      {"coco_rle", coco_rle},
      {"mask_png", mask_png},
      {"depth_image", depth_image},
      {"ply", ply}};
  const auto it = targets.find(target);
  if (it == targets.end()) throw std::invalid_argument("no fuzz target " + target);
  it->second(bytes.data(), bytes.size());
}

}  // namespace gslift::fuzz
