// Writes the binary seed files of the fuzz corpora (fuzz/make_seeds.sh adds the text ones from
// tests/data): each with the project's own writers, so the seeds are what gslift itself
// produces. Usage: fuzz_make_seeds SEEDS_DIR (one folder per target inside).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz/fuzz_support.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/splat/ply_io.hpp"

namespace fs = std::filesystem;
using namespace gslift;

namespace {

std::string bytes_of(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

template <class T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// One PINHOLE camera, two images (one with a keypoint), two points with tracks: the layout of
// COLMAP's WriteCamerasBinary / WriteImagesBinary / WritePoints3DBinary.
std::string colmap_binary_model() {
  std::string cams, ims, pts;
  put<uint64_t>(cams, 1);
  put<int32_t>(cams, 1);
  put<int32_t>(cams, 1);
  put<uint64_t>(cams, 8);
  put<uint64_t>(cams, 6);
  for (double p : {10.0, 10.0, 4.0, 3.0}) put(cams, p);
  put<uint64_t>(ims, 2);
  for (uint32_t i = 1; i <= 2; ++i) {
    put<uint32_t>(ims, i);
    for (double q : {1.0, 0.0, 0.0, 0.0, double(i), 0.0, 2.0}) put(ims, q);
    put<uint32_t>(ims, 1);
    const std::string name = "cam_0" + std::to_string(i) + ".png";
    ims.append(name.c_str(), name.size() + 1);
    put<uint64_t>(ims, i - 1);
    for (uint32_t k = 0; k + 1 < i; ++k) {
      put<double>(ims, 1.5);
      put<double>(ims, 2.5);
      put<int64_t>(ims, 1);
    }
  }
  put<uint64_t>(pts, 2);
  for (uint64_t p = 1; p <= 2; ++p) {
    put<uint64_t>(pts, p);
    for (double x : {0.1 * p, 0.2, 1.0}) put(pts, x);
    for (uint8_t c : {10, 20, 30}) put(pts, c);
    put<double>(pts, 0.5);
    put<uint64_t>(pts, 1);
    put<int32_t>(pts, 2);
    put<int32_t>(pts, 0);
  }
  return cams + fuzz::kSplit + ims + fuzz::kSplit + pts;
}

// `inner` inside `levels` nested arrays, or objects {"a": ...}: issue 33's deeply nested
// documents, which parsed fine and then overflowed the stack when dumped or copied
// (base/json_read.hpp caps the depth). Made here rather than committed; each stays under the
// 1 MB -max_len of bench/fuzz/run.sh, which would cut a larger seed short.
std::string nested(size_t levels, const std::string& inner, bool objects = false) {
  std::string s;
  for (size_t i = 0; i < levels; ++i) s += objects ? "{\"a\":" : "[";
  return s + inner + std::string(levels, objects ? '}' : ']');
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SEEDS_DIR\n", argv[0]);
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path tmp = out / ".tmp";
  for (const char* d : {"colmap_binary", "coco_rle", "mask_png", "depth_image", "ply", "vlm_reply",
                        "transforms_json", ".tmp"})
    fs::create_directories(out / d);

  constexpr size_t kDeep = 200000;
  fuzz::write_file(out / "vlm_reply/deep_arrays.txt", nested(kDeep, "1"));
  fuzz::write_file(out / "vlm_reply/deep_objects.txt", nested(kDeep / 2, "1", /*objects=*/true));
  fuzz::write_file(out / "transforms_json/deep_matrix.json",
                   "{\"frames\": [{\"file_path\": \"images/r_0.png\", \"transform_matrix\": " +
                       nested(kDeep, "0") + "}]}");
  fuzz::write_file(out / "coco_rle/deep_counts.json",
                   "[{\"size\": [6, 8], \"counts\": " + nested(kDeep, "1") + "}]");

  fuzz::write_file(out / "colmap_binary/model.bin", colmap_binary_model());

  cv::Mat1b mask(6, 8, uchar(0));
  mask(cv::Rect(2, 1, 3, 4)) = 255;
  const std::string record = sam_mask_record(mask, 0.9, 0.95).dump();
  fuzz::write_file(out / "coco_rle/auto.json", "[" + record + "]");
  fuzz::write_file(out / "coco_rle/box.json",
                   "[" + record + ", null, {\"size\": [6, 8], \"counts\": [10, 5, 33]}]");

  cv::Mat labels(6, 8, CV_32SC1, cv::Scalar(0));
  labels(cv::Rect(1, 1, 4, 3)) = 300;
  write_label_png16(tmp / "labels.png", labels);
  fuzz::write_file(out / "mask_png/labels16.png", bytes_of(tmp / "labels.png"));
  write_rgb_png(tmp / "mask8.png", cv::Mat(6, 8, CV_8UC3, cv::Scalar::all(255)));
  fuzz::write_file(out / "mask_png/rgb8.png", bytes_of(tmp / "mask8.png"));

  cv::Mat1f depth(6, 8, 1.5f);
  depth(2, 3) = 0;
  write_depth_png_mm(tmp / "depth.png", depth);
  write_depth_tiff(tmp / "depth.tiff", depth);
  // The first byte picks the extension in depth_image_fuzz.cpp: even = .png, odd = .tiff.
  fuzz::write_file(out / "depth_image/depth_png",
                   std::string(1, '\0') + bytes_of(tmp / "depth.png"));
  fuzz::write_file(out / "depth_image/depth_tiff",
                   std::string(1, '\1') + bytes_of(tmp / "depth.tiff"));

  GaussianModel model;
  model.sh_degree = 1;
  model.feature_dim = 2;
  model.resize(3);
  model.instance_ids.assign(3, 7);
  for (size_t i = 0; i < 3; ++i) model.quats[i * 4] = 1;
  write_ply(model, tmp / "model.ply");
  fuzz::write_file(out / "ply/degree1_features.ply", bytes_of(tmp / "model.ply"));
  fs::remove_all(tmp);
  return 0;
}
