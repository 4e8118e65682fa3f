#include "nodes/ingest/depth_registration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "nodes/ingest/opencv_camera.hpp"

namespace gslift {

namespace {

// A depth pixel's surface point in the colour camera: its pixel position there, its colour-frame
// z and the depth-frame z it was measured at. ok = valid and in front of the colour camera.
struct ColourVertex {
  double u = 0, v = 0, z = 0, measured = 0;
  bool ok = false;
};

// sqrt(2) tan(86 deg): the depth difference across a depth pixel's diagonal of a surface seen 86
// degrees from its normal, per unit of z and depth-camera focal length.
constexpr double kEdgeSpreadPerPixel = 20.2;

// The largest squared normalised radius the colour image sees, padded by 20%: a point beyond it
// is off the image, and OpenCV's rational model, which is not monotonic far outside the
// calibrated field, would otherwise fold it back onto the image.
double visible_radius2(const Camera& c) {
  std::vector<cv::Point2d> border;
  for (int u = 0; u <= c.width; ++u)
    border.push_back({double(u), 0}), border.push_back({double(u), double(c.height)});
  for (int v = 0; v <= c.height; ++v)
    border.push_back({0, double(v)}), border.push_back({double(c.width), double(v)});
  double r2 = 0;
  for (const auto& p : pixel_rays(c, border)) r2 = std::max(r2, p.x * p.x + p.y * p.y);
  return 1.44 * r2;
}

// Writes the triangle's perspective-correct depth into the pixels whose centres it covers,
// nearer values winning.
void draw_triangle(const ColourVertex& a, const ColourVertex& b, const ColourVertex& c,
                   cv::Mat& out) {
  const double area = (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
  if (std::abs(area) < 1e-12) return;
  const int i0 = std::max(0, static_cast<int>(std::ceil(std::min({a.u, b.u, c.u}) - 0.5)));
  const int i1 =
      std::min(out.cols - 1, static_cast<int>(std::floor(std::max({a.u, b.u, c.u}) - 0.5)));
  const int j0 = std::max(0, static_cast<int>(std::ceil(std::min({a.v, b.v, c.v}) - 0.5)));
  const int j1 =
      std::min(out.rows - 1, static_cast<int>(std::floor(std::max({a.v, b.v, c.v}) - 0.5)));
  constexpr double kEdge = -1e-9;  // pixel centres on a shared edge belong to both triangles
  for (int j = j0; j <= j1; ++j) {
    const double py = j + 0.5;
    float* row = out.ptr<float>(j);
    for (int i = i0; i <= i1; ++i) {
      const double px = i + 0.5;
      const double wa = ((b.u - px) * (c.v - py) - (b.v - py) * (c.u - px)) / area;
      const double wb = ((c.u - px) * (a.v - py) - (c.v - py) * (a.u - px)) / area;
      const double wc = 1 - wa - wb;
      if (wa < kEdge || wb < kEdge || wc < kEdge) continue;
      const float z = static_cast<float>(1.0 / (wa / a.z + wb / b.z + wc / c.z));
      if (row[i] == 0 || z < row[i]) row[i] = z;
    }
  }
}

}  // namespace

cv::Mat register_depth(const cv::Mat& depth, const DepthSensor& sensor, const Camera& colour) {
  const Camera& dc = sensor.camera;
  if (depth.type() != CV_32FC1 || depth.cols != dc.width || depth.rows != dc.height)
    throw std::invalid_argument(
        "register_depth: the depth map must be CV_32FC1 of the depth "
        "camera's size");
  const int w = depth.cols, h = depth.rows;
  std::vector<cv::Point2d> centres;
  centres.reserve(static_cast<size_t>(w) * h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) centres.push_back({u + 0.5, v + 0.5});
  const std::vector<cv::Point2d> rays = pixel_rays(dc, centres);

  // Every valid depth pixel moved into the colour frame; those in front of the colour camera and
  // within its field are projected.
  const Eigen::Matrix3d& R = sensor.depth_to_colour.R;
  const Eigen::Vector3d& t = sensor.depth_to_colour.t;
  const double max_r2 = visible_radius2(colour);
  std::vector<ColourVertex> vertices(centres.size());
  std::vector<cv::Point3d> points;
  std::vector<size_t> index;
  for (size_t k = 0; k < centres.size(); ++k) {
    const double z = depth.at<float>(static_cast<int>(k / w), static_cast<int>(k % w));
    if (!(z > 0) || !std::isfinite(z)) continue;
    const Eigen::Vector3d x = R * Eigen::Vector3d(rays[k].x * z, rays[k].y * z, z) + t;
    if (x.z() <= 1e-6) continue;
    const double nx = x.x() / x.z(), ny = x.y() / x.z();
    if (nx * nx + ny * ny > max_r2) continue;
    points.push_back({x.x(), x.y(), x.z()});
    index.push_back(k);
    vertices[k].z = x.z();
    vertices[k].measured = z;
  }
  const std::vector<cv::Point2d> pixels = project_to_pixels(colour, points);
  for (size_t n = 0; n < index.size(); ++n) {
    ColourVertex& vx = vertices[index[n]];
    vx.u = pixels[n].x;
    vx.v = pixels[n].y;
    vx.ok = true;
  }

  cv::Mat out(colour.height, colour.width, CV_32FC1, cv::Scalar(0));
  const double spread_per_z = kEdgeSpreadPerPixel / std::sqrt(dc.fx * dc.fy);
  // One surface unless the measured depths spread more than a steep surface's would.
  auto one_surface = [&](const ColourVertex& a, const ColourVertex& b, const ColourVertex& c) {
    const double lo = std::min({a.measured, b.measured, c.measured});
    const double hi = std::max({a.measured, b.measured, c.measured});
    return hi - lo <= spread_per_z * lo;
  };
  auto draw = [&](const ColourVertex& a, const ColourVertex& b, const ColourVertex& c) {
    if (one_surface(a, b, c)) draw_triangle(a, b, c, out);
  };
  for (int v = 0; v + 1 < h; ++v)
    for (int u = 0; u + 1 < w; ++u) {
      const ColourVertex& p00 = vertices[static_cast<size_t>(v) * w + u];
      const ColourVertex& p10 = vertices[static_cast<size_t>(v) * w + u + 1];
      const ColourVertex& p01 = vertices[static_cast<size_t>(v + 1) * w + u];
      const ColourVertex& p11 = vertices[static_cast<size_t>(v + 1) * w + u + 1];
      const int valid = p00.ok + p10.ok + p01.ok + p11.ok;
      if (valid == 4) {
        draw(p00, p10, p01);
        draw(p10, p11, p01);
      } else if (valid == 3) {
        if (!p00.ok) draw(p10, p11, p01);
        if (!p10.ok) draw(p00, p11, p01);
        if (!p01.ok) draw(p00, p10, p11);
        if (!p11.ok) draw(p00, p10, p01);
      }
    }
  return out;
}

}  // namespace gslift
