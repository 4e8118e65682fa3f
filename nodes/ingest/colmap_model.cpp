#include "nodes/ingest/colmap_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <limits>
#include <locale>
#include <set>
#include <sstream>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "nodes/ingest/colmap_camera_model.hpp"
#include "nodes/ingest/numeric_text.hpp"

namespace gslift {
namespace {

namespace fs = std::filesystem;

Pose pose_from_colmap(double qw, double qx, double qy, double qz, const Eigen::Vector3d& t,
                      const std::string& where) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  // The text reader refuses "nan" and "inf" as numbers; the binary one reads them as doubles.
  if (!(std::isfinite(q.norm()) && t.allFinite()))
    throw InputError(where + ": the pose holds NaN or Inf");
  if (!(q.norm() > 1e-12)) throw InputError(where + ": zero rotation quaternion");
  Pose p;
  p.R = q.normalized().toRotationMatrix();
  p.t = t;
  return p;
}

// A sparse point's coordinate as stored (float): NaN, Inf and values beyond float's range are
// refused (the binary reader used to pass them on, and reconstruction collapsed to one Gaussian).
float point_coordinate(double x, const std::string& where) {
  if (!(std::abs(x) <= std::numeric_limits<float>::max()))
    throw InputError(where + ": point coordinate " + std::to_string(x) +
                     " is NaN, Inf or out of range");
  return static_cast<float>(x);
}

// Shared by both readers: deterministic view order and referential integrity.
void finish(ColmapModel& m, const fs::path& images_file) {
  std::set<std::string> names;
  for (const auto& im : m.images) {
    if (!m.cameras.count(im.camera_id))
      throw InputError(images_file.string() + ": image '" + im.name + "' refers to camera " +
                       std::to_string(im.camera_id) + ", which is not in the cameras file");
    if (!names.insert(im.name).second)
      throw InputError(images_file.string() + ": image name '" + im.name + "' appears twice");
  }
  std::sort(m.images.begin(), m.images.end(),
            [](const ColmapImage& a, const ColmapImage& b) { return a.name < b.name; });
}

// ---- text ----------------------------------------------------------------------------------

// Calls fn(tokens, "file:line") for every non-empty, non-comment line. With `pairs`, the line
// after each such line is consumed too and passed as `next` (images.txt's POINTS2D line, which
// may be empty).
template <class Fn>
void for_each_record(const fs::path& file, Fn fn) {
  require_regular_file(file, "COLMAP model file");
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open");
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto tokens = split_whitespace(line);
    if (tokens.empty() || tokens[0][0] == '#') continue;
    fn(tokens, file.string() + ":" + std::to_string(n), in, n);
  }
}

ColmapModel read_text(const fs::path& folder) {
  ColmapModel m;
  for_each_record(
      folder / "cameras.txt", [&](const auto& tok, const std::string& where, auto&, int&) {
        if (tok.size() < 4)
          throw InputError(where + ": expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS");
        const auto& model = colmap_camera_model(tok[1], where);
        std::vector<double> params;
        for (size_t i = 4; i < tok.size(); ++i)
          params.push_back(parse_double(tok[i], where, "param"));
        const int id = static_cast<int>(parse_integer(tok[0], where, "CAMERA_ID"));
        const long long w = parse_integer(tok[2], where, "WIDTH"),
                        h = parse_integer(tok[3], where, "HEIGHT");
        check_image_size(w, h, where);  // before narrowing to int
        m.cameras[id] =
            camera_from_colmap(model, static_cast<int>(w), static_cast<int>(h), params, where);
      });
  for_each_record(folder / "images.txt", [&](const auto& tok, const std::string& where,
                                             std::istream& in, int& n) {
    if (tok.size() != 10)
      throw InputError(where + ": expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, got " +
                       std::to_string(tok.size()) + " fields");
    static const char* kNames[] = {"IMAGE_ID", "QW", "QX", "QY", "QZ", "TX", "TY", "TZ"};
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = parse_double(tok[i], where, kNames[i]);
    ColmapImage im;
    im.id = static_cast<int>(parse_integer(tok[0], where, "IMAGE_ID"));
    im.camera_id = static_cast<int>(parse_integer(tok[8], where, "CAMERA_ID"));
    im.name = tok[9];
    im.pose = pose_from_colmap(v[1], v[2], v[3], v[4], {v[5], v[6], v[7]}, where);
    m.images.push_back(std::move(im));
    std::string points2d;  // keypoints are not used by gslift
    if (std::getline(in, points2d)) ++n;
  });
  const fs::path points = folder / "points3D.txt";
  if (fs::exists(points))
    for_each_record(points, [&](const auto& tok, const std::string& where, auto&, int&) {
      if (tok.size() < 8) throw InputError(where + ": expected POINT3D_ID X Y Z R G B ERROR");
      Eigen::Vector3f x;
      Eigen::Matrix<uint8_t, 3, 1> c;
      for (int i = 0; i < 3; ++i) {
        x[i] = point_coordinate(parse_double(tok[1 + i], where, "coordinate"), where);
        const long long ci = parse_integer(tok[4 + i], where, "colour");
        if (ci < 0 || ci > 255) throw InputError(where + ": colour must be in [0, 255]");
        c[i] = static_cast<uint8_t>(ci);
      }
      m.points.xyz.push_back(x);
      m.points.rgb.push_back(c);
    });
  finish(m, folder / "images.txt");
  return m;
}

// ---- binary --------------------------------------------------------------------------------

// Little-endian reads that name the file when it ends early.
class BinaryFile {
 public:
  explicit BinaryFile(const fs::path& path)
      : path_((require_regular_file(path, "COLMAP model file"), path)),
        in_(path, std::ios::binary) {
    if (!in_) throw InputError(path.string() + ": cannot open");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<uint64_t>(in_.tellg());
    in_.seekg(0);
  }
  template <class T>
  T read() {
    T v;
    if (!in_.read(reinterpret_cast<char*>(&v), sizeof v)) truncated();
    return v;
  }
  std::string read_string() {
    std::string s;
    char c;
    while (true) {
      if (!in_.get(c)) truncated();
      if (c == '\0') return s;
      s.push_back(c);
    }
  }
  void skip(uint64_t bytes) {
    if (bytes > remaining()) truncated();
    in_.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
  }
  // A record count read from the file, checked against the bytes left so that a corrupt count
  // fails cleanly instead of allocating without bound.
  uint64_t read_count(uint64_t min_record_bytes) {
    const uint64_t n = read<uint64_t>();
    if (min_record_bytes > 0 && n > remaining() / min_record_bytes) truncated();
    return n;
  }
  uint64_t remaining() { return size_ - static_cast<uint64_t>(in_.tellg()); }
  [[noreturn]] void truncated() {
    throw InputError(path_.string() + ": truncated or corrupt COLMAP binary file");
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  std::ifstream in_;
  uint64_t size_ = 0;
};

ColmapModel read_binary(const fs::path& folder) {
  ColmapModel m;
  {
    BinaryFile f(folder / "cameras.bin");
    const uint64_t n = f.read_count(24);
    for (uint64_t i = 0; i < n; ++i) {
      const int id = f.read<int32_t>();
      const std::string where = f.path().string() + " (camera " + std::to_string(id) + ")";
      const auto& model = colmap_camera_model(f.read<int32_t>(), where);
      const uint64_t w = f.read<uint64_t>(), h = f.read<uint64_t>();
      const uint64_t most = uint64_t(1) << 62;  // signed for check_image_size, still absurd
      check_image_size(static_cast<long long>(std::min(w, most)),
                       static_cast<long long>(std::min(h, most)), where);
      std::vector<double> params(model.num_params);
      for (auto& p : params) p = f.read<double>();
      m.cameras[id] =
          camera_from_colmap(model, static_cast<int>(w), static_cast<int>(h), params, where);
    }
  }
  {
    BinaryFile f(folder / "images.bin");
    const uint64_t n = f.read_count(73);
    for (uint64_t i = 0; i < n; ++i) {
      ColmapImage im;
      im.id = static_cast<int>(f.read<uint32_t>());
      double v[7];
      for (auto& x : v) x = f.read<double>();
      im.camera_id = static_cast<int>(f.read<uint32_t>());
      im.name = f.read_string();
      im.pose = pose_from_colmap(v[0], v[1], v[2], v[3], {v[4], v[5], v[6]},
                                 f.path().string() + " (image " + im.name + ")");
      const uint64_t num_points2d = f.read_count(24);
      f.skip(num_points2d * 24);  // x, y (double) and point3D id (int64) per keypoint
      m.images.push_back(std::move(im));
    }
  }
  const fs::path points = folder / "points3D.bin";
  if (fs::exists(points)) {
    BinaryFile f(points);
    const uint64_t n = f.read_count(51);
    m.points.xyz.reserve(n);
    m.points.rgb.reserve(n);
    for (uint64_t i = 0; i < n; ++i) {
      f.read<uint64_t>();  // point id
      Eigen::Vector3f x;
      for (int k = 0; k < 3; ++k)
        x[k] = point_coordinate(f.read<double>(),
                                f.path().string() + " (point " + std::to_string(i) + ")");
      Eigen::Matrix<uint8_t, 3, 1> c;
      for (int k = 0; k < 3; ++k) c[k] = f.read<uint8_t>();
      f.read<double>();  // reprojection error
      const uint64_t track = f.read_count(8);
      f.skip(track * 8);  // (image id, point2D index) int32 pairs
      m.points.xyz.push_back(x);
      m.points.rgb.push_back(c);
    }
  }
  finish(m, folder / "images.bin");
  return m;
}

}  // namespace

ColmapModel read_colmap_text(const fs::path& folder) {
  return read_text(folder);
}

ColmapModel read_colmap_binary(const fs::path& folder) {
  return read_binary(folder);
}

ColmapModel read_colmap_model(const fs::path& folder) {
  if (fs::exists(folder / "cameras.bin") && fs::exists(folder / "images.bin"))
    return read_binary(folder);
  if (fs::exists(folder / "cameras.txt") && fs::exists(folder / "images.txt"))
    return read_text(folder);
  throw InputError(folder.string() +
                   ": no COLMAP model (looked for cameras.bin + images.bin and cameras.txt + "
                   "images.txt)");
}

void write_colmap_text(const fs::path& folder, const ColmapModel& model) {
  auto stream = [] {
    std::ostringstream s;
    s.imbue(std::locale::classic());
    s << std::setprecision(17);
    return s;
  };
  std::ostringstream cams = stream();
  cams << "# Camera list with one line of data per camera:\n"
          "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
  for (const auto& [id, cam] : model.cameras) {
    const auto [name, params] = colmap_params_of(cam);
    cams << id << ' ' << name << ' ' << cam.width << ' ' << cam.height;
    for (double p : params) cams << ' ' << p;
    cams << '\n';
  }
  std::ostringstream ims = stream();
  ims << "# Image list with two lines of data per image:\n"
         "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
         "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
  for (const auto& im : model.images) {
    Eigen::Quaterniond q(im.pose.R);
    q.normalize();
    if (q.w() < 0) q.coeffs() *= -1;  // one of the two equivalent quaternions, deterministically
    ims << im.id << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
        << im.pose.t.x() << ' ' << im.pose.t.y() << ' ' << im.pose.t.z() << ' ' << im.camera_id
        << ' ' << im.name << "\n\n";
  }
  std::ostringstream pts = stream();
  pts << "# 3D point list with one line of data per point:\n"
         "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n";
  for (size_t i = 0; i < model.points.size(); ++i) {
    const auto& x = model.points.xyz[i];
    const auto& c = model.points.rgb[i];
    pts << i + 1 << ' ' << x.x() << ' ' << x.y() << ' ' << x.z() << ' ' << int(c[0]) << ' '
        << int(c[1]) << ' ' << int(c[2]) << " 0\n";
  }
  fs::create_directories(folder);
  write_file_atomically(folder / "cameras.txt", cams.str());
  write_file_atomically(folder / "images.txt", ims.str());
  write_file_atomically(folder / "points3D.txt", pts.str());
}

}  // namespace gslift
