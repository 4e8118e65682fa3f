#include "nodes/scene/image_io.hpp"

#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

TEST_CASE("RGB round trip keeps RGB channel order") {
  const auto dir = test::scratch_dir("image_io_rgb");
  cv::Mat rgb(2, 3, CV_8UC3, cv::Scalar(10, 20, 30));
  rgb.at<cv::Vec3b>(1, 2) = {200, 100, 50};
  write_rgb_png(dir / "a.png", rgb);
  // On disk OpenCV order is BGR: the red value 10 must be the third channel of the raw file.
  cv::Mat raw = cv::imread((dir / "a.png").string(), cv::IMREAD_UNCHANGED);
  REQUIRE(raw.at<cv::Vec3b>(0, 0) == cv::Vec3b(30, 20, 10));
  cv::Mat back = read_rgb(dir / "a.png");
  REQUIRE(back.type() == CV_8UC3);
  CHECK(cv::norm(back, rgb, cv::NORM_INF) == 0);
}

TEST_CASE("RGBA is composited onto the background and alpha stays readable") {
  const auto dir = test::scratch_dir("image_io_rgba");
  cv::Mat bgra(1, 2, CV_8UC4);
  bgra.at<cv::Vec4b>(0, 0) = {0, 0, 255, 255};  // opaque red
  bgra.at<cv::Vec4b>(0, 1) = {0, 0, 255, 51};   // red at alpha 0.2
  cv::imwrite((dir / "a.png").string(), bgra);
  cv::Mat rgb = read_rgb(dir / "a.png");
  CHECK(rgb.at<cv::Vec3b>(0, 0) == cv::Vec3b(255, 0, 0));
  // 0.2 * 255 + 0.8 * 255 = 255 for red; 0.8 * 255 = 204 for green and blue.
  CHECK(rgb.at<cv::Vec3b>(0, 1) == cv::Vec3b(255, 204, 204));
  cv::Mat black = read_rgb(dir / "a.png", cv::Scalar(0, 0, 0));
  CHECK(black.at<cv::Vec3b>(0, 1) == cv::Vec3b(51, 0, 0));
  cv::Mat alpha = read_alpha(dir / "a.png");
  REQUIRE(alpha.type() == CV_8UC1);
  CHECK(alpha.at<uchar>(0, 1) == 51);
}

TEST_CASE("depth: 16-bit PNG divided by scale, float TIFF as is") {
  const auto dir = test::scratch_dir("image_io_depth");
  cv::Mat1f d(2, 2);
  d << 1.2345f, 0.f, 70.f, -1.f;
  write_depth_png_mm(dir / "d.png", d);
  cv::Mat mm = read_depth(dir / "d.png", 1000);
  REQUIRE(mm.type() == CV_32FC1);
  CHECK(mm.at<float>(0, 0) == Approx(1.235f));  // rounded to the millimetre
  CHECK(mm.at<float>(1, 0) == 0.f);             // 70 m does not fit 16-bit mm: invalid
  CHECK(mm.at<float>(1, 1) == 0.f);
  // The same file read with Replica's scale 6553.5: 1235 / 6553.5.
  CHECK(read_depth(dir / "d.png", 6553.5).at<float>(0, 0) == Approx(1235 / 6553.5));

  write_depth_tiff(dir / "d.tiff", d);
  cv::Mat f = read_depth(dir / "d.tiff", 1000);
  CHECK(f.at<float>(0, 0) == 1.2345f);
  CHECK(f.at<float>(1, 0) == 70.f);
  CHECK(f.at<float>(1, 1) == 0.f);  // negative -> invalid

  cv::imwrite((dir / "d.exr").string(), d);
  CHECK(read_depth(dir / "d.exr", 1000).at<float>(0, 0) == 1.2345f);
}

TEST_CASE("label maps: 16-bit round trip, 8-bit accepted, colour and overflow rejected") {
  const auto dir = test::scratch_dir("image_io_labels");
  cv::Mat1i ids(1, 3);
  ids << 0, 300, 65535;
  write_label_png16(dir / "l.png", ids);
  cv::Mat back = read_label_map(dir / "l.png");
  REQUIRE(back.type() == CV_32SC1);
  CHECK(cv::norm(back, ids, cv::NORM_INF) == 0);

  cv::imwrite((dir / "l8.png").string(), cv::Mat1b(1, 2, uchar(7)));
  CHECK(read_label_map(dir / "l8.png").at<int>(0, 1) == 7);
  CHECK_THROWS_WITH(read_label_map(dir / "l8.png", false), Contains("l8.png") && Contains("8-bit"));

  cv::imwrite((dir / "c.png").string(), cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3)));
  CHECK_THROWS_WITH(read_label_map(dir / "c.png"), Contains("c.png") && Contains("colour"));

  ids(0, 2) = 65536;
  CHECK_THROWS_WITH(write_label_png16(dir / "big.png", ids), Contains("big.png"));
  CHECK_FALSE(std::filesystem::exists(dir / "big.png"));
}

TEST_CASE("float TIFF keeps three channels exactly") {
  const auto dir = test::scratch_dir("image_io_float");
  cv::Mat3f n(1, 2);
  n(0, 0) = {0.f, 0.6f, 0.8f};
  n(0, 1) = {-1.f, 0.f, 0.f};
  write_float_tiff(dir / "n.tiff", n);
  cv::Mat back = read_float_tiff(dir / "n.tiff");
  REQUIRE(back.type() == CV_32FC3);
  CHECK(cv::norm(back, n, cv::NORM_INF) == 0);
}

TEST_CASE("unreadable image files give InputError naming the file") {
  const auto dir = test::scratch_dir("image_io_bad");
  CHECK_THROWS_AS(read_rgb(dir / "absent.png"), InputError);
  CHECK_THROWS_WITH(read_rgb(dir / "absent.png"), Contains("absent.png"));
  std::ofstream(dir / "junk.png") << "not a png";
  CHECK_THROWS_WITH(read_depth(dir / "junk.png", 1000), Contains("junk.png"));
  cv::imwrite((dir / "d8.png").string(), cv::Mat1b(2, 2, uchar(3)));
  CHECK_THROWS_WITH(read_depth(dir / "d8.png", 1000), Contains("d8.png") && Contains("8-bit"));
  // A broken PNG signature with "DICM" at offset 128 is a DICOM file to OpenCV's sniffing (GDCM
  // aborted on it): refused by its first bytes before any decoder sees it.
  std::string dicm = "\x89PNG\r\n" + std::string(122, '\xff') + "DICM";
  std::ofstream(dir / "dicm.png", std::ios::binary) << dicm;
  CHECK_THROWS_WITH(
      read_label_map(dir / "dicm.png"),
      Contains("dicm.png") && Contains("not a PNG, JPEG, TIFF, BMP, WebP or OpenEXR"));
}

TEST_CASE("float TIFF files hold channels in memory order and exact values") {
  const auto dir = test::scratch_dir("image_io_float_order");
  cv::Mat3f n(1, 1, cv::Vec3f(0.1f, 0.2f, 0.3f));
  write_float_tiff(dir / "n.tiff", n);
  // Uncompressed float32 TIFF: the 12 pixel bytes follow the 8-byte header.
  std::ifstream in(dir / "n.tiff", std::ios::binary);
  in.seekg(8);
  float raw[3];
  in.read(reinterpret_cast<char*>(raw), sizeof raw);
  CHECK(raw[0] == 0.1f);
  CHECK(raw[2] == 0.3f);
}
