// Hostile input to the readers (issue 16, docs/security.md): declared sizes checked against the
// file before allocating, absurd image sizes, NaN in binary models, files that are directories,
// FIFOs or /dev/zero, unreadable optional entries, and names that leave the capture folder.
// Each is an InputError naming the file.
#include <sys/stat.h>

#include <cstdint>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "base/errors.hpp"
#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/coco_rle.hpp"
#include "nodes/ingest/colmap_model.hpp"
#include "nodes/ingest/nerf_transforms.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/ingest/vlm_reply.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/splat/initialise.hpp"
#include "nodes/splat/ply_io.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "tests/ingest/small_capture.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

std::string read_bytes(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

void write_bytes(const fs::path& f, const std::string& bytes) {
  std::ofstream(f, std::ios::binary) << bytes;
}

// Replaces the first `from` in file `f` by `to`.
void patch(const fs::path& f, const std::string& from, const std::string& to) {
  std::string s = read_bytes(f);
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  s.replace(at, from.size(), to);
  write_bytes(f, s);
}

GaussianModel two_gaussians() {
  GaussianModel m;
  m.sh_degree = 0;
  m.resize(2);
  for (size_t i = 0; i < 2; ++i) {
    m.quats[i * 4] = 1;
    m.means[i * 3 + 2] = 2 + float(i);
  }
  return m;
}

template <class T>
void put(std::ofstream& out, T v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof v);
}

// A binary COLMAP model of one 8 x 6 PINHOLE camera and one image, with `tx` as its translation
// and `point_x` as the x of one 3D point.
void write_binary_model(const fs::path& dir, double tx, double point_x) {
  fs::create_directories(dir);
  std::ofstream cams(dir / "cameras.bin", std::ios::binary);
  put<uint64_t>(cams, 1);
  put<int32_t>(cams, 1);
  put<int32_t>(cams, 1);  // PINHOLE
  put<uint64_t>(cams, 8);
  put<uint64_t>(cams, 6);
  for (double p : {10.0, 10.0, 4.0, 3.0}) put(cams, p);
  std::ofstream ims(dir / "images.bin", std::ios::binary);
  put<uint64_t>(ims, 1);
  put<uint32_t>(ims, 1);
  for (double q : {1.0, 0.0, 0.0, 0.0, tx, 0.0, 2.0}) put(ims, q);
  put<uint32_t>(ims, 1);
  ims.write("cam_00.png", 11);
  put<uint64_t>(ims, 0);
  std::ofstream pts(dir / "points3D.bin", std::ios::binary);
  put<uint64_t>(pts, 1);
  put<uint64_t>(pts, 1);
  for (double x : {point_x, 0.0, 1.0}) put(pts, x);
  for (uint8_t c : {1, 2, 3}) put(pts, c);
  put<double>(pts, 0.5);
  put<uint64_t>(pts, 0);
}

}  // namespace

TEST_CASE("a PLY declaring more vertices than its file holds is refused before allocating",
          "[hostile]") {
  const fs::path dir = test::scratch_dir("hostile_ply");
  const fs::path good = dir / "good.ply";
  write_ply(two_gaussians(), good);
  CHECK(read_ply(good).size() == 2);
  for (const std::string count : {"30000000", "100000000", "4294967296", "10000000000"}) {
    const fs::path f = dir / ("count_" + count + ".ply");
    fs::copy_file(good, f);
    patch(f, "element vertex 2\n", "element vertex " + count + "\n");
    CHECK_THROWS_WITH(read_ply(f),
                      Contains(f.string() + ": PLY data truncated: the header declares " + count +
                               " vertices, but the file holds"));
  }
  const fs::path negative = dir / "negative.ply";
  fs::copy_file(good, negative);
  patch(negative, "element vertex 2\n", "element vertex -1\n");
  CHECK_THROWS_WITH(read_ply(negative), Contains("malformed PLY line 'element vertex -1'"));
  // ASCII: at least two characters a value.
  const fs::path ascii = dir / "ascii.ply";
  std::string text = read_bytes(good);
  text = text.substr(0, text.find("end_header\n") + 11);
  text.replace(text.find("binary_little_endian"), 20, "ascii");
  text.replace(text.find("element vertex 2"), 16, "element vertex 100000000");
  write_bytes(ascii, text + "0 0 0 0 0 0 0 0 0 0 0 0 0 0\n");
  CHECK_THROWS_WITH(read_ply(ascii), Contains("declares 100000000 vertices"));
  CHECK_THROWS_WITH(read_ply("/dev/zero"), Contains("/dev/zero: PLY file is not a regular file"));
}

TEST_CASE("COLMAP binary: NaN and Inf are refused like the text reader does", "[hostile]") {
  const fs::path dir = test::scratch_dir("hostile_colmap_nan");
  write_binary_model(dir / "ok", 0.5, 1.0);
  const ColmapModel ok = read_colmap_binary(dir / "ok");
  CHECK(ok.images.size() == 1);
  CHECK(ok.points.xyz[0].x() == 1.0f);
  write_binary_model(dir / "nan_pose", std::nan(""), 1.0);
  CHECK_THROWS_WITH(read_colmap_binary(dir / "nan_pose"),
                    Contains("images.bin (image cam_00.png): the pose holds NaN or Inf"));
  write_binary_model(dir / "inf_point", 0.5, HUGE_VAL);
  CHECK_THROWS_WITH(read_colmap_binary(dir / "inf_point"),
                    Contains("points3D.bin (point 0): point coordinate"));
  write_binary_model(dir / "huge_point", 0.5, 1e300);  // beyond float: undefined as a cast
  CHECK_THROWS_WITH(read_colmap_binary(dir / "huge_point"), Contains("out of range"));
  // A huge keypoint count in a tiny images.bin fails on the count, not on an allocation.
  write_binary_model(dir / "count", 0.5, 1.0);
  patch(dir / "count/images.bin", std::string("cam_00.png\0", 11) + std::string(8, '\0'),
        std::string("cam_00.png\0", 11) + std::string(7, '\0') + "\x7f");
  CHECK_THROWS_WITH(read_colmap_binary(dir / "count"), Contains("truncated or corrupt"));
}

TEST_CASE("absurd image sizes are refused before anything is allocated", "[hostile]") {
  const fs::path capture = test::write_small_capture("hostile_sizes", "");
  const fs::path cameras = capture / "sparse/0/cameras.txt";
  const std::string original = read_bytes(cameras);
  for (const std::string size : {"30000 30000", "1000000000 1000000000", "10000000000 1"}) {
    write_bytes(cameras, original);
    patch(cameras, "PINHOLE 8 6", "PINHOLE " + size);
    CHECK_THROWS_WITH(load_capture(capture),
                      Contains(cameras.string() + ":3: image size") &&
                          Contains("over gslift's limit of 67108864 pixels"));
  }
  // A PNG whose header claims 100000 x 100000 is refused from the header, before decoding.
  const fs::path png = capture / "huge.png";
  cv::imwrite(png.string(), cv::Mat(6, 8, CV_8UC3, cv::Scalar::all(7)));
  std::string bytes = read_bytes(png);
  const unsigned char claim[8] = {0, 1, 0x86, 0xA0, 0, 1, 0x86, 0xA0};  // 100000, 100000
  bytes.replace(16, 8, reinterpret_cast<const char*>(claim), 8);
  write_bytes(png, bytes);
  CHECK_THROWS_WITH(read_rgb(png), Contains(png.string() + " (PNG header): image size 100000 x "
                                                           "100000 is over gslift's limit"));
  // splat.render refuses a 30000 x 30000 camera up front (it used to allocate 24 GB).
  RenderSettings settings;
  CHECK_THROWS_AS(
      render(two_gaussians(), test::centred_pinhole(30000, 30000, 1000), Pose(), settings),
      InputError);
  // COCO RLE: [0, 0] and a size far beyond any image, whatever the counts.
  CHECK_THROWS_WITH(
      parse_sam_auto_masks(R"([{"segmentation": {"size": [0, 0], "counts": ""}}])", "a.json"),
      Contains("a.json mask 0 (RLE size [height, width]): image size must be "
               "positive"));
  CHECK_THROWS_WITH(
      rle_decode_json(nlohmann::json::parse(R"({"size": [100000, 100000], "counts": "0"})"),
                      "b.json"),
      Contains("b.json (RLE size [height, width]): image size 100000 x 100000 is over"));
  CHECK_THROWS_WITH(
      rle_decode_json(nlohmann::json::parse(R"({"size": [10000000000, 1], "counts": [1]})"),
                      "c.json"),
      Contains("c.json (RLE size"));
}

TEST_CASE("directories, FIFOs and /dev/zero where a capture file belongs are named", "[hostile]") {
  const fs::path capture = test::write_small_capture("hostile_not_files", "");
  fs::remove(capture / "capture.yaml");
  fs::create_directories(capture / "capture.yaml");
  CHECK_THROWS_WITH(load_capture(capture), Contains((capture / "capture.yaml").string() +
                                                    ": capture.yaml is a directory, not a file"));
  fs::remove(capture / "capture.yaml");
  REQUIRE(::mkfifo((capture / "capture.yaml").c_str(), 0600) == 0);
  CHECK_THROWS_WITH(load_capture(capture), Contains("capture.yaml is not a regular file"));
  fs::remove(capture / "capture.yaml");
  const fs::path images = capture / "sparse/0/images.txt";
  fs::remove(images);
  fs::create_symlink("/dev/zero", images);
  CHECK_THROWS_WITH(load_capture(capture),
                    Contains(images.string() + ": COLMAP model file is not a regular file"));
  fs::remove(images);
  fs::create_symlink(images, images);  // a loop
  CHECK_THROWS_AS(load_capture(capture), InputError);
}

TEST_CASE("unreadable depth, SAM and VLM entries are errors naming them, not 'missing'",
          "[hostile]") {
  const fs::path capture = test::write_small_capture("hostile_entries", "");
  {  // a depth prior that is a directory
    fs::remove(capture / "depth/cam_01.png");
    fs::create_directories(capture / "depth/cam_01.png");
    CHECK_THROWS_WITH(load_capture(capture), Contains((capture / "depth/cam_01.png").string() +
                                                      ": view file is a directory"));
    fs::remove(capture / "depth/cam_01.png");
    fs::create_symlink(capture / "nowhere.png", capture / "depth/cam_01.png");  // dangling
    CHECK_THROWS_WITH(load_capture(capture), Contains("cam_01.png: view file does not exist"));
    fs::remove(capture / "depth/cam_01.png");
  }
  const Capture c = load_capture(capture);
  fs::create_directories(capture / "sam_auto/cam_00.json");
  CHECK_THROWS_WITH(load_sam_auto_masks(c), Contains("sam_auto/cam_00.json: input file is a "
                                                     "directory"));
  fs::create_directories(capture / "vlm/cam_00");
  fs::create_symlink(capture / "nowhere.txt", capture / "vlm/cam_00/round_0.txt");
  CHECK_THROWS_WITH(load_vlm_boxes(c, VlmLoadOptions{}, nullptr),
                    Contains("round_0.txt: input file does not exist"));
}

TEST_CASE("JSON nested 100,000 levels deep is an InputError naming the file, not a crash",
          "[hostile]") {
  // Issue 33: these parsed, then overflowed the stack when the value was copied or dumped.
  std::string objects;
  for (int i = 0; i < 100000; ++i) objects += "{\"a\":";
  objects += "1" + std::string(100000, '}');
  const std::string arrays = std::string(200000, '[') + "0" + std::string(200000, ']');
  VlmFrame frame;
  frame.image_width = 64;
  frame.image_height = 48;
  CHECK_THROWS_WITH(parse_vlm_reply(objects, frame, 0, "vlm/cam_00/round_0.txt"),
                    Contains("vlm/cam_00/round_0.txt (round 0): invalid JSON") &&
                        Contains("nested more than 256 levels"));
  CHECK_THROWS_WITH(
      parse_sam_auto_masks("[{\"size\": [6, 8], \"counts\": " + arrays + "}]",
                           "sam_auto/cam_00.json"),
      Contains("sam_auto/cam_00.json: invalid JSON") && Contains("nested more than 256 levels"));
  const fs::path dir = test::scratch_dir("hostile_deep_json");
  write_bytes(dir / "transforms.json",
              R"({"frames": [{"file_path": "r_0.png", "transform_matrix": )" + arrays + "}]}");
  CHECK_THROWS_WITH(
      read_nerf_transforms(dir / "transforms.json"),
      Contains("transforms.json: invalid JSON") && Contains("nested more than 256 levels"));
}

TEST_CASE("names that leave the capture folder are refused unless allowed", "[hostile]") {
  const fs::path capture = test::write_small_capture("hostile_escape", "");
  const fs::path images = capture / "sparse/0/images.txt";
  const std::string original = read_bytes(images);
  // A real image outside the capture, reached by ../, an absolute path and a symlink.
  const fs::path outside = test::scratch_dir("hostile_escape_outside");
  fs::copy_file(capture / "images/cam_00.png", outside / "cam_00.png");
  for (const std::string& name : {std::string("../../hostile_escape_outside/cam_00.png"),
                                  (outside / "cam_00.png").string(), std::string("link.png")}) {
    write_bytes(images, original);
    patch(images, "cam_00.png", name);
    if (name == "link.png") fs::create_symlink(outside / "cam_00.png", capture / "images/link.png");
    CHECK_THROWS_WITH(load_capture(capture),
                      Contains("(image '" + name + "'): '" + name + "' points outside") &&
                          Contains("allow_outside_paths"));
    CaptureOptions trusted;
    trusted.allow_outside_paths = true;
    CHECK(load_capture(capture, trusted).views.size() == 3);
  }
  write_bytes(images, "1 1 0 0 0 0 0 2 1 ../../../../../../etc/passwd\n\n");
  CHECK_THROWS_WITH(load_capture(capture), Contains("points outside"));
  write_bytes(images, original);
  // capture.yaml folders.
  std::ofstream(capture / "capture.yaml", std::ios::app) << "sam_auto: /etc\n";
  CHECK_THROWS_WITH(load_capture(capture),
                    Contains("capture.yaml (sam_auto): '/etc' points outside"));
  // transforms.json frames.
  const fs::path nerf = test::scratch_dir("hostile_escape_nerf");
  std::ofstream(nerf / "transforms.json")
      << R"({"fl_x": 10, "w": 8, "h": 6, "frames": [{"file_path": "../hostile_escape_outside/cam_00.png",
           "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
  CHECK_THROWS_WITH(load_capture(nerf), Contains("transforms.json frame 0: "
                                                 "'../hostile_escape_outside/cam_00.png' points "
                                                 "outside"));
}

TEST_CASE("symlinks out of every annotation folder are refused, not only images/", "[hostile]") {
  // Issue 33: depth/, gt/, vlm/, sam_auto/ and sam_box/ followed links out of the capture (an
  // outside file's boxes were used; /etc/passwd was opened and its first bytes quoted).
  const fs::path capture = test::write_small_capture("hostile_links_out", "");
  const fs::path outside = test::scratch_dir("hostile_links_out_outside");
  fs::copy_file(capture / "depth/cam_01.png", outside / "depth.png");
  fs::copy_file(capture / "gt/instance/cam_01.png", outside / "instance.png");
  const auto relink = [&](const fs::path& link, const fs::path& target) {
    fs::remove(link);
    fs::create_symlink(target, link);
  };
  relink(capture / "depth/cam_01.png", outside / "depth.png");
  CHECK_THROWS_WITH(
      load_capture(capture),
      Contains("view file: '" + (capture / "depth/cam_01.png").string() + "' points outside"));
  CaptureOptions trusted;
  trusted.allow_outside_paths = true;
  CHECK(load_capture(capture, trusted).views.size() == 3);
  relink(capture / "depth/cam_01.png", outside / "depth.png");
  fs::rename(outside / "depth.png", capture / "depth_real.png");
  relink(capture / "depth/cam_01.png", "../depth_real.png");  // a link that stays inside: fine
  CHECK(load_capture(capture).views.size() == 3);

  relink(capture / "gt/instance/cam_01.png", outside / "instance.png");
  CHECK_THROWS_WITH(load_capture(capture), Contains("gt/instance/cam_01.png' points outside"));
  fs::remove(capture / "gt/instance/cam_01.png");
  fs::copy_file(outside / "instance.png", capture / "gt/instance/cam_01.png");
  std::ofstream(outside / "classes.yaml") << "classes: {1: table}\n";
  relink(capture / "gt/classes.yaml", outside / "classes.yaml");
  CHECK_THROWS_WITH(load_capture(capture), Contains("classes.yaml' points outside"));
  fs::remove(capture / "gt/classes.yaml");

  const Capture c = load_capture(capture);
  fs::create_directories(capture / "vlm/cam_00");
  fs::create_symlink("/etc/passwd", capture / "vlm/cam_00/round_0.txt");
  CHECK_THROWS_WITH(load_vlm_boxes(c, VlmLoadOptions{}, nullptr),
                    Contains("VLM reply: '" + (capture / "vlm/cam_00/round_0.txt").string() +
                             "' points outside"));
  fs::remove_all(capture / "vlm");
  fs::create_directories(capture / "sam_auto");
  std::ofstream(outside / "masks.json") << "[]";
  fs::create_symlink(outside / "masks.json", capture / "sam_auto/cam_00.json");
  CHECK_THROWS_WITH(load_sam_auto_masks(c), Contains("cam_00.json' points outside"));
  BoxSet boxes;
  boxes.views.push_back(ViewBoxes{});
  boxes.views[0].view = "cam_00";
  boxes.views[0].rounds = 1;
  fs::create_directories(capture / "sam_box/cam_00");
  fs::create_symlink(outside / "masks.json", capture / "sam_box/cam_00/round_0.json");
  CHECK_THROWS_WITH(load_sam_box_masks(c, boxes), Contains("round_0.json' points outside"));
}

TEST_CASE("an extreme pose or focal length is named before Open3D's voxel grid", "[hostile]") {
  ColouredPoints points;
  points.xyz = {{0, 0, 0}, {1e12, 0, 0}};
  points.rgb = {{0, 0, 0}, {1, 1, 1}};
  points.normals = {{0, 0, 0}, {0, 0, 0}};
  CHECK_THROWS_WITH(gaussians_from_points(points, 1e-3, InitialiseOptions{}),
                    Contains("voxel size 0.001000 m for points spanning") &&
                        Contains("needs more than 2^31 voxels per axis"));
  points.xyz[1].x() = std::nan("");
  CHECK_THROWS_WITH(gaussians_from_points(points, 1e-3, InitialiseOptions{}),
                    Contains("a point is NaN or Inf"));
}
