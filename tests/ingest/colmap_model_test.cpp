#include "nodes/ingest/colmap_model.hpp"

#include <cstdint>
#include <fstream>

#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kText = test::test_data("ingest/colmap_text");

// Writes tests/data/ingest/colmap_text as a COLMAP binary model, field by field as COLMAP's
// WriteCamerasBinary / WriteImagesBinary / WritePoints3DBinary do.
class BinaryWriter {
 public:
  explicit BinaryWriter(const fs::path& p) : out_(p, std::ios::binary) {}
  template <class T>
  BinaryWriter& put(T v) {
    out_.write(reinterpret_cast<const char*>(&v), sizeof v);
    return *this;
  }
  BinaryWriter& str(const std::string& s) {
    out_.write(s.c_str(), s.size() + 1);
    return *this;
  }

 private:
  std::ofstream out_;
};

void write_fixture_binary(const fs::path& dir) {
  struct Cam {
    int32_t id, model;
    std::vector<double> params;
  };
  const std::vector<Cam> cams{{1, 0, {50, 32, 24}},
                              {2, 1, {50, 51, 31.5, 23.5}},
                              {3, 2, {50, 32, 24, 0.1}},
                              {4, 3, {50, 32, 24, 0.1, -0.02}},
                              {5, 4, {50, 51, 32, 24, 0.1, -0.02, 0.001, -0.002}}};
  {
    BinaryWriter w(dir / "cameras.bin");
    w.put<uint64_t>(cams.size());
    for (const auto& c : cams) {
      w.put(c.id).put(c.model).put<uint64_t>(64).put<uint64_t>(48);
      for (double p : c.params) w.put(p);
    }
  }
  {
    const double s = 0.70710678118654757;
    BinaryWriter w(dir / "images.bin");
    w.put<uint64_t>(3);
    // Deliberately not in name order: the reader sorts by name.
    auto image = [&](uint32_t id, std::vector<double> qt, uint32_t cam, const char* name,
                     uint64_t num_points2d) {
      w.put(id);
      for (double v : qt) w.put(v);
      w.put(cam).str(name).put(num_points2d);
      for (uint64_t i = 0; i < num_points2d; ++i) w.put(10.5).put(20.5).put<int64_t>(-1);
    };
    image(3, {s, 0, s, 0, 1, 2, 3}, 5, "c.png", 2);
    image(1, {1, 0, 0, 0, 0, 0, 4}, 1, "a.png", 0);
    image(2, {0, 0, 0, 1, 0.5, 0, 0}, 3, "b.png", 0);
  }
  {
    BinaryWriter w(dir / "points3D.bin");
    w.put<uint64_t>(2);
    w.put<uint64_t>(1).put(0.5).put(-1.0).put(2.0).put<uint8_t>(255).put<uint8_t>(128);
    w.put<uint8_t>(0).put(0.7).put<uint64_t>(2).put<int32_t>(3).put<int32_t>(0);
    w.put<int32_t>(1).put<int32_t>(0);
    w.put<uint64_t>(2).put(0.0).put(0.0).put(4.0).put<uint8_t>(10).put<uint8_t>(20);
    w.put<uint8_t>(30).put(0.1).put<uint64_t>(0);
  }
}

// The assertions both readers must pass: hand-computed from the fixture.
void check_fixture(const ColmapModel& m) {
  REQUIRE(m.cameras.size() == 5);
  const Camera& sp = m.cameras.at(1);
  CHECK(sp.width == 64);
  CHECK(sp.height == 48);
  CHECK(sp.fx == 50);
  CHECK(sp.fy == 50);
  CHECK(sp.cx == 32);
  CHECK(sp.distortion.empty());
  const Camera& ph = m.cameras.at(2);
  CHECK(ph.fy == 51);
  CHECK(ph.cx == 31.5);
  CHECK(ph.cy == 23.5);
  CHECK(ph.distortion.empty());
  CHECK(m.cameras.at(3).distortion == std::vector<double>{0.1, 0, 0, 0});
  CHECK(m.cameras.at(4).distortion == std::vector<double>{0.1, -0.02, 0, 0});
  CHECK(m.cameras.at(5).distortion == std::vector<double>{0.1, -0.02, 0.001, -0.002});
  CHECK(m.cameras.at(5).fy == 51);

  REQUIRE(m.images.size() == 3);
  CHECK(m.images[0].name == "a.png");
  CHECK(m.images[1].name == "b.png");
  CHECK(m.images[2].name == "c.png");
  CHECK(m.images[2].id == 3);
  CHECK(m.images[2].camera_id == 5);
  // a: identity rotation, camera 4 units behind the origin along -z: centre (0, 0, -4).
  CHECK((m.images[0].pose.centre() - Eigen::Vector3d(0, 0, -4)).norm() < 1e-12);
  // b: 180 degrees about z.
  Eigen::Matrix3d rz = Eigen::Vector3d(-1, -1, 1).asDiagonal();
  CHECK((m.images[1].pose.R - rz).norm() < 1e-12);
  // c: 90 degrees about y maps world x to camera -z... R = [[0,0,1],[0,1,0],[-1,0,0]].
  Eigen::Matrix3d ry;
  ry << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  CHECK((m.images[2].pose.R - ry).norm() < 1e-12);
  CHECK((m.images[2].pose.t - Eigen::Vector3d(1, 2, 3)).norm() == 0);

  REQUIRE(m.points.size() == 2);
  CHECK(m.points.xyz[0] == Eigen::Vector3f(0.5f, -1.f, 2.f));
  CHECK(m.points.rgb[0] == Eigen::Matrix<uint8_t, 3, 1>(255, 128, 0));
  CHECK(m.points.xyz[1] == Eigen::Vector3f(0.f, 0.f, 4.f));
  CHECK(m.points.rgb[1] == Eigen::Matrix<uint8_t, 3, 1>(10, 20, 30));
}

void copy_text_fixture(const fs::path& dir) {
  for (const char* f : {"cameras.txt", "images.txt", "points3D.txt"})
    fs::copy_file(kText / f, dir / f);
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_all(const fs::path& p, const std::string& s) {
  std::ofstream(p, std::ios::binary) << s;
}

}  // namespace

TEST_CASE("COLMAP text and binary readers give the same model") {
  SECTION("text") {
    check_fixture(read_colmap_text(kText));
  }
  SECTION("binary") {
    const auto dir = test::scratch_dir("colmap_binary");
    write_fixture_binary(dir);
    check_fixture(read_colmap_binary(dir));
    check_fixture(read_colmap_model(dir));
  }
}

TEST_CASE("COLMAP binary wins over text when both exist") {
  const auto dir = test::scratch_dir("colmap_both");
  write_fixture_binary(dir);
  ColmapModel one_image = read_colmap_text(kText);
  one_image.images.resize(1);
  write_colmap_text(dir, one_image);
  CHECK(read_colmap_model(dir).images.size() == 3);
  fs::remove(dir / "images.bin");
  CHECK(read_colmap_model(dir).images.size() == 1);
}

TEST_CASE("COLMAP text writer round-trips doubles exactly") {
  const auto dir = test::scratch_dir("colmap_write");
  ColmapModel m = read_colmap_text(kText);
  m.cameras[2].fx = 0.1 + 0.2;  // not representable in 16 digits
  m.images[0].pose.t = {1.0 / 3.0, -2e-17, 1e10};
  write_colmap_text(dir, m);
  const ColmapModel back = read_colmap_text(dir);
  CHECK(back.cameras.at(2).fx == m.cameras[2].fx);
  CHECK(back.cameras.at(5).distortion == m.cameras[5].distortion);
  // OpenCV's rational model (k4..k6 != 0) is written as FULL_OPENCV and read back whole.
  m.cameras[5].distortion = {0.1, -0.2, 0.001, 0.002, 0.03, 0.4, -0.05, 0.006};
  write_colmap_text(dir, m);
  CHECK(read_colmap_text(dir).cameras.at(5).distortion == m.cameras[5].distortion);
  CHECK(back.images[0].pose.t == m.images[0].pose.t);
  for (size_t i = 0; i < m.images.size(); ++i)
    CHECK((back.images[i].pose.R - m.images[i].pose.R).norm() < 1e-15);
  CHECK(back.points.xyz == m.points.xyz);
  // SIMPLE_RADIAL comes back as OPENCV with the same distortion.
  CHECK(
      read_all(dir / "cameras.txt").find("3 OPENCV 64 48 50 50 32 24 0.10000000000000001 0 0 0") !=
      std::string::npos);
}

TEST_CASE("COLMAP binary truncated at any byte gives InputError naming the file") {
  const auto dir = test::scratch_dir("colmap_truncated");
  write_fixture_binary(dir);
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    const std::string full = read_all(dir / name);
    for (size_t len = 0; len < full.size(); ++len) {
      write_all(dir / name, full.substr(0, len));
      INFO(name << " truncated to " << len << " bytes");
      CHECK_THROWS_WITH(read_colmap_binary(dir), Contains(name));
    }
    write_all(dir / name, full);
  }
  check_fixture(read_colmap_binary(dir));
}

TEST_CASE("COLMAP broken files give InputError naming the file and line") {
  const auto dir = test::scratch_dir("colmap_broken");
  copy_text_fixture(dir);
  const std::string images = read_all(dir / "images.txt");
  const std::string cameras = read_all(dir / "cameras.txt");
  auto replaced = [](std::string s, const std::string& from, const std::string& to) {
    return s.replace(s.find(from), from.size(), to);
  };
  SECTION("non-numeric field") {
    write_all(dir / "images.txt", replaced(images, "0.5 0 0 3 b.png", "0.5 zero 0 3 b.png"));
    CHECK_THROWS_WITH(read_colmap_text(dir), Contains("images.txt:8") && Contains("'zero'"));
  }
  SECTION("missing field") {
    write_all(dir / "images.txt", replaced(images, "0.5 0 0 3 b.png", "0.5 0 3 b.png"));
    CHECK_THROWS_WITH(read_colmap_text(dir), Contains("images.txt:8"));
  }
  SECTION("unknown camera model") {
    write_all(dir / "cameras.txt", replaced(cameras, "1 SIMPLE_PINHOLE", "1 THIN_PRISM_FISHEYE"));
    CHECK_THROWS_WITH(read_colmap_text(dir), Contains("cameras.txt:3") &&
                                                 Contains("THIN_PRISM_FISHEYE") &&
                                                 Contains("PINHOLE"));
  }
  SECTION("wrong parameter count") {
    write_all(dir / "cameras.txt", replaced(cameras, "50 51 31.5 23.5", "50 51 31.5"));
    CHECK_THROWS_WITH(read_colmap_text(dir), Contains("cameras.txt:4") && Contains("4 param"));
  }
  SECTION("image of an absent camera") {
    write_all(dir / "images.txt", replaced(images, "0.5 0 0 3 b.png", "0.5 0 0 9 b.png"));
    CHECK_THROWS_WITH(read_colmap_text(dir), Contains("images.txt") && Contains("camera 9"));
  }
  SECTION("no model at all") {
    fs::remove(dir / "cameras.txt");
    CHECK_THROWS_WITH(read_colmap_model(dir), Contains("cameras.bin") && Contains("cameras.txt"));
  }
}

TEST_CASE("COLMAP binary with an unknown camera model id is rejected") {
  const auto dir = test::scratch_dir("colmap_bad_model");
  write_fixture_binary(dir);
  std::string cams = read_all(dir / "cameras.bin");
  cams[8 + 4] = 99;  // model id of the first camera
  write_all(dir / "cameras.bin", cams);
  CHECK_THROWS_WITH(read_colmap_binary(dir), Contains("cameras.bin") && Contains("model id 99"));
}

TEST_CASE("COLMAP models of DTU scan 24") {
  GSLIFT_REQUIRE_SHARED_DATA("dtu_scan24");
  const ColmapModel text = read_colmap_model(test::shared_data("dtu_scan24/colmap"));
  REQUIRE(text.images.size() == 49);
  CHECK(text.images[0].name == "000000.png");
  CHECK(text.cameras.at(1).fx == Approx(2892.330631));
  CHECK(text.cameras.at(1).width == 1600);
  CHECK(text.points.size() == 0);
  // The unit-sphere frame: every camera looks at the origin from ~2.8 units away.
  for (const auto& im : text.images) {
    const double d = im.pose.centre().norm();
    CHECK(d > 2);
    CHECK(d < 4);
    CHECK(im.pose.to_camera(Eigen::Vector3d::Zero()).z() > 0);
  }

  const ColmapModel bin = read_colmap_model(test::shared_data("dtu_scan24/sparse/0"));
  CHECK(bin.images.size() == 49);
  CHECK(bin.points.size() == 34673);
  for (const auto& [id, cam] : bin.cameras) {
    REQUIRE(cam.distortion.size() == 4);  // SIMPLE_RADIAL
    CHECK(cam.distortion[0] > 0.01);      // small barrel-free radial term, k1 ~ 0.02-0.06
    CHECK(cam.distortion[0] < 0.07);
    CHECK(cam.fx == cam.fy);
    CHECK(cam.fx > 2850);  // the IDR calibration says ~2892 px
    CHECK(cam.fx < 2950);
    CHECK(cam.width == 1600);
    CHECK(cam.cx == Approx(800).margin(50));
  }
}
