#include "tests/ingest/small_capture.hpp"

#include <fstream>

#include "nodes/ingest/colmap_model.hpp"
#include "nodes/scene/image_io.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

namespace gslift::test {

namespace fs = std::filesystem;

fs::path write_small_capture(const std::string& name, const std::string& manifest_extra) {
  const auto dir = scratch_dir(name);
  ColmapModel m;
  m.cameras[1] = centred_pinhole(8, 6, 10);
  for (int i = 0; i < 3; ++i) {
    ColmapImage im;
    im.id = i + 1;
    im.camera_id = 1;
    im.name = std::string("cam_0") + char('0' + i) + ".png";
    im.pose.t = Eigen::Vector3d(i, 0, 2);
    m.images.push_back(im);
    const std::string stem = im.name.substr(0, 6);
    write_rgb_png(dir / "images" / im.name, cv::Mat(6, 8, CV_8UC3, cv::Scalar(i, 2 * i, 3 * i)));
    write_depth_png_mm(dir / "depth" / (stem + ".png"), cv::Mat1f(6, 8, 1.5f + i));
    write_label_png16(dir / "gt/instance" / (stem + ".png"), cv::Mat1i(6, 8, 300 + i));
  }
  m.points.xyz.push_back({1, 2, 3});
  m.points.rgb.push_back({4, 5, 6});
  write_colmap_text(dir / "sparse/0", m);
  std::ofstream(dir / "capture.yaml") << "format: gslift.capture/v1\nname: small\nmodel: sparse/0\n"
                                         "images: images\ndepth: {folder: depth, scale: 1000}\n"
                                         "gt: gt\n"
                                      << manifest_extra;
  std::ofstream(dir / "gt/classes.yaml") << "classes: {1: table, 2: surgeon}\n"
                                            "instances: {300: 1, 301: 2}\n";
  return dir;
}

}  // namespace gslift::test
