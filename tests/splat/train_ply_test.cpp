// INRIA PLY layout: exact header, write -> read round trip, and a handmade reference-style file.
#include <fstream>

#include "base/random.hpp"
#include "nodes/splat/ply_io.hpp"
#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

GaussianModel random_model(size_t n, int degree, int features, bool ids) {
  GaussianModel m;
  m.sh_degree = degree;
  m.feature_dim = features;
  if (ids) {
    m.instance_ids.assign(n, 0);
    m.class_ids.assign(n, 0);
  }
  m.resize(n);
  RandomStream rng(42);
  for (auto* v : {&m.means, &m.log_scales, &m.quats, &m.opacity_logits, &m.sh, &m.features})
    for (auto& x : *v) x = static_cast<float>(rng.uniform(-2.0, 2.0));
  for (size_t i = 0; i < n && ids; ++i) {
    m.instance_ids[i] = static_cast<int>(i) - 1;
    m.class_ids[i] = static_cast<int>(i * 7);
  }
  return m;
}

std::string header_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string header, line;
  while (std::getline(in, line)) {
    header += line + "\n";
    if (line == "end_header") break;
  }
  return header;
}

}  // namespace

TEST_CASE("ply header follows the INRIA property order exactly") {
  const auto dir = test::scratch_dir("train_ply_header");
  write_ply(random_model(2, 1, 2, true), dir / "m.ply");
  const std::string expected =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\n"
      "property float f_rest_0\nproperty float f_rest_1\nproperty float f_rest_2\n"
      "property float f_rest_3\nproperty float f_rest_4\nproperty float f_rest_5\n"
      "property float f_rest_6\nproperty float f_rest_7\nproperty float f_rest_8\n"
      "property float opacity\n"
      "property float scale_0\nproperty float scale_1\nproperty float scale_2\n"
      "property float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty float rot_3\n"
      "property float feat_0\nproperty float feat_1\n"
      "property int instance_id\nproperty int class_id\nend_header\n";
  CHECK(header_of(dir / "m.ply") == expected);
  // 28 floats + 2 ints per vertex.
  CHECK(std::filesystem::file_size(dir / "m.ply") == expected.size() + 2 * 30 * 4);
}

TEST_CASE("ply write then read round-trips every field") {
  const auto dir = test::scratch_dir("train_ply_roundtrip");
  for (int degree : {0, 3}) {
    const GaussianModel m = random_model(5, degree, degree == 0 ? 0 : 3, degree == 3);
    write_ply(m, dir / "m.ply");
    const GaussianModel r = read_ply(dir / "m.ply");
    CHECK(r.sh_degree == degree);
    CHECK(r.feature_dim == m.feature_dim);
    CHECK(r.means == m.means);
    CHECK(r.log_scales == m.log_scales);
    CHECK(r.quats == m.quats);
    CHECK(r.opacity_logits == m.opacity_logits);
    CHECK(r.sh == m.sh);
    CHECK(r.features == m.features);
    CHECK(r.instance_ids == m.instance_ids);
    CHECK(r.class_ids == m.class_ids);
  }
}

TEST_CASE("a handmade reference-3DGS PLY loads with channel-major f_rest") {
  // tests/data/splat/inria_degree1.ply: 2 Gaussians, SH degree 1, binary little endian as the INRIA
  // code writes it (made by tests/data/splat/make_inria_ply.py), values chosen so that property
  // index p of vertex i holds 100 i + p.
  const GaussianModel m = read_ply(test::test_data("splat/inria_degree1.ply"));
  REQUIRE(m.size() == 2);
  CHECK(m.sh_degree == 1);
  CHECK(m.feature_dim == 0);
  CHECK(m.instance_ids.empty());
  const int K = 4;
  for (int i = 0; i < 2; ++i) {
    const float base = 100.f * i;
    CHECK(m.means[i * 3 + 2] == base + 2);
    CHECK(m.sh[i * K * 3 + 1] == base + 7);  // f_dc_1 is property 7
    // f_rest_{c*3 + k-1} is property 9 + c*3 + k-1: coefficient k=2 of green (c=1) is 9+3+1.
    CHECK(m.sh[(i * K + 2) * 3 + 1] == base + 13);
    CHECK(m.opacity_logits[i] == base + 18);
    CHECK(m.log_scales[i * 3 + 0] == base + 19);
    CHECK(m.quats[i * 4 + 0] == base + 22);
    CHECK(m.quats[i * 4 + 3] == base + 25);
  }
}

TEST_CASE("bad PLY files raise InputError naming the file") {
  const auto dir = test::scratch_dir("train_ply_bad");
  std::ofstream(dir / "noscale.ply")
      << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
         "end_header\n1\n";
  CHECK_THROWS_WITH(read_ply(dir / "noscale.ply"),
                    Catch::Contains("noscale.ply") && Catch::Contains("lacks property 'y'"));
  write_ply(random_model(3, 0, 0, false), dir / "trunc.ply");
  std::filesystem::resize_file(dir / "trunc.ply",
                               std::filesystem::file_size(dir / "trunc.ply") - 8);
  CHECK_THROWS_AS(read_ply(dir / "trunc.ply"), InputError);
  CHECK_THROWS_WITH(read_ply(dir / "trunc.ply"), Catch::Contains("truncated"));
  CHECK_THROWS_AS(read_ply(dir / "missing.ply"), InputError);
}
