#include "viewer/view_server.hpp"

#include <unistd.h>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>
#include <tuple>

#include <httplib.h>
#include <sys/socket.h>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "nodes/splat/ply_io.hpp"
#include "viewer/viewer_page.hpp"

namespace gslift {
namespace {

using nlohmann::json;

constexpr int kMaxFrameSide = 4096;

double number(const std::string& name, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    throw InputError("'" + name + "' must be a number");
  return v;
}

std::vector<double> numbers(const std::string& name, const std::string& text, size_t count) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(number(name, item));
  if (out.size() != count)
    throw InputError("'" + name + "' must be " + std::to_string(count) + " numbers");
  return out;
}

std::string param(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name.c_str())) throw InputError("missing parameter '" + name + "'");
  return req.get_param_value(name.c_str());
}

int view_index(const httplib::Request& req, const Capture& capture) {
  const double v = number("view", param(req, "view"));
  if (v != std::floor(v) || v < 0 || v >= static_cast<double>(capture.views.size()))
    throw InputError("'view' must be a view index below " + std::to_string(capture.views.size()));
  return static_cast<int>(v);
}

// A camera from named values (query parameters or a JSON object's members as text).
template <typename Get>
std::pair<Camera, Pose> camera_from(Get get) {
  Camera c;
  const double w = number("w", get("w")), h = number("h", get("h"));
  if (w != std::floor(w) || h != std::floor(h) || w < 8 || h < 8 || w > kMaxFrameSide ||
      h > kMaxFrameSide)
    throw InputError("'w' and 'h' must be whole numbers from 8 to " +
                     std::to_string(kMaxFrameSide));
  c.width = static_cast<int>(w);
  c.height = static_cast<int>(h);
  c.fx = number("fx", get("fx"));
  c.fy = number("fy", get("fy"));
  c.cx = number("cx", get("cx"));
  c.cy = number("cy", get("cy"));
  if (c.fx <= 0 || c.fy <= 0) throw InputError("'fx' and 'fy' must be positive");
  const std::vector<double> r = numbers("R", get("R"), 9), t = numbers("t", get("t"), 3);
  Pose p;
  for (int i = 0; i < 9; ++i) p.R(i / 3, i % 3) = r[i];
  p.t = Eigen::Vector3d(t[0], t[1], t[2]);
  // Re-orthonormalise: the page composes rotations in doubles, but a hand-made URL may not.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(p.R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  p.R = svd.matrixU() * svd.matrixV().transpose();
  if (p.R.determinant() < 0) throw InputError("'R' must be a rotation");
  return {c, p};
}

std::string json_text(const json& j, const char* key) {
  if (!j.contains(key)) throw InputError(std::string("missing '") + key + "'");
  const json& v = j[key];
  if (v.is_number()) return v.dump();
  if (v.is_array()) {
    std::string s;
    for (const json& x : v) {
      if (!x.is_number()) throw InputError(std::string("'") + key + "' must hold numbers");
      s += (s.empty() ? "" : ",") + x.dump();
    }
    return s;
  }
  throw InputError(std::string("'") + key + "' must be a number or a list of numbers");
}

std::vector<cv::Point> points(const json& body, const char* key) {
  std::vector<cv::Point> out;
  if (!body.contains(key)) return out;
  if (!body[key].is_array()) throw InputError(std::string("'") + key + "' must be a list");
  for (const json& p : body[key]) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw InputError(std::string("'") + key + "' must hold [x, y] pairs");
    out.emplace_back(static_cast<int>(std::floor(p[0].get<double>())),
                     static_cast<int>(std::floor(p[1].get<double>())));
  }
  return out;
}

json body_json(const httplib::Request& req) {
  const json j = parse_json_or_discarded(req.body);
  if (j.is_discarded() || !j.is_object()) throw InputError("the body must be a JSON object");
  return j;
}

std::string encode(const cv::Mat& rgb_or_gray, const char* ext) {
  cv::Mat out = rgb_or_gray;
  if (out.channels() == 3) cv::cvtColor(rgb_or_gray, out, cv::COLOR_RGB2BGR);
  std::vector<uchar> bytes;
  const std::vector<int> jpeg = {cv::IMWRITE_JPEG_QUALITY, 90};
  cv::imencode(ext, out, bytes, std::string(ext) == ".jpg" ? jpeg : std::vector<int>{});
  return std::string(bytes.begin(), bytes.end());
}

std::string hex(cv::Vec3b c) {
  char s[8];
  std::snprintf(s, sizeof s, "#%02x%02x%02x", c[0], c[1], c[2]);
  return s;
}

json info(const ViewScene& scene) {
  json views = json::array();
  for (size_t v = 0; v < scene.capture.views.size(); ++v) {
    const View& view = scene.capture.views[v];
    json r = json::array(), t = json::array();
    for (int i = 0; i < 9; ++i) r.push_back(view.pose.R(i / 3, i % 3));
    for (int i = 0; i < 3; ++i) t.push_back(view.pose.t[i]);
    views.push_back({{"index", v},
                     {"name", view.name},
                     {"w", view.camera.width},
                     {"h", view.camera.height},
                     {"fx", view.camera.fx},
                     {"fy", view.camera.fy},
                     {"cx", view.camera.cx},
                     {"cy", view.camera.cy},
                     {"R", r},
                     {"t", t},
                     {"held_out", view.held_out},
                     {"photo", view.rgb.present()},
                     {"ground_truth", view.gt_semantic.present()}});
  }
  const GaussianModel& m = scene.model;
  std::vector<int64_t> counts(scene.instance_labels.size(), 0);
  for (int32_t id : m.instance_ids)
    if (id >= 0 && id < static_cast<int32_t>(counts.size())) ++counts[id];
  json instances = json::array();
  for (size_t k = 0; k < scene.instance_labels.size(); ++k)
    instances.push_back({{"id", k},
                         {"label", scene.instance_labels[k]},
                         {"colour", hex(ViewSession::instance_colour(static_cast<int>(k)))},
                         {"gaussians", counts[k]}});
  json classes = json::array();
  for (const auto& [id, name] : scene.capture.classes)
    if (id != 0) classes.push_back(name);
  // The scene's centre and extent (the median Gaussian and the spread around it) for orbiting.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (size_t g = 0; g < m.size(); ++g)
    centre += Eigen::Vector3d(m.means[3 * g], m.means[3 * g + 1], m.means[3 * g + 2]);
  centre /= static_cast<double>(m.size());
  return {{"title", scene.title},
          {"gaussians", m.size()},
          {"features", m.feature_dim > 0},
          {"text_queries", scene.encoder != nullptr && !scene.instance_labels.empty()},
          {"centre", {centre.x(), centre.y(), centre.z()}},
          {"views", views},
          {"instances", instances},
          {"classes", classes},
          {"metrics", scene.metrics_markdown}};
}

json summary_json(const SelectionSummary& s) {
  return {{"selected", s.selected},
          {"latency_ms", s.latency_ms},
          {"query_class", s.query_class},
          {"instances", s.instances}};
}

}  // namespace

// Debian's libcpp-httplib listens with a backlog of 5 (compiled in): 1000 clients connecting at
// once overflow it, and the kernel drops their SYNs until a retry a second or more later. A
// second listen() on the bound socket raises the backlog (Linux), so they queue instead.
constexpr int kListenBacklog = 1024;

struct ViewServer::Impl {
  ViewSession& session;
  httplib::Server server;
  int socket = -1;  // the listening socket, seen in set_socket_options
  // stop() may come before serve() has entered httplib's loop, whose stop() then does nothing.
  std::atomic<bool> serving{false}, stop_requested{false}, returned{false};
  explicit Impl(ViewSession& s) : session(s) {}
};

ViewServer::ViewServer(ViewSession& session) : impl_(std::make_unique<Impl>(session)) {
  httplib::Server& s = impl_->server;
  s.set_socket_options([impl = impl_.get()](int sock) {
    const int yes = 1;  // what httplib's default options do: a restarted viewer rebinds at once
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    impl->socket = sock;
  });
  ViewSession& session_ref = session;
  // Every handler's bad input becomes 400 with the message; anything else 500. The server goes on.
  s.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        std::string message = "internal error";
        int status = 500;
        try {
          std::rethrow_exception(ep);
        } catch (const InputError& e) {
          message = e.what();
          status = 400;
        } catch (const json::exception& e) {
          message = e.what();
          status = 400;
        } catch (const std::exception& e) {
          message = e.what();
        }
        res.status = status;
        res.set_content(json{{"error", message}}.dump(), "application/json");
      });
  // 404 and httplib's own 400s get a JSON body too (a handler's 400 keeps its message).
  s.set_error_handler(httplib::Server::Handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    res.set_content(json{{"error", "HTTP " + std::to_string(res.status)}}.dump(),
                    "application/json");
  }));
  s.Get("/", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(kViewerPage, "text/html; charset=utf-8");
  });
  s.Get("/api/info", [&session_ref](const httplib::Request&, httplib::Response& res) {
    res.set_content(info(session_ref.scene()).dump(), "application/json");
  });
  s.Get("/api/frame", [&session_ref](const httplib::Request& req, httplib::Response& res) {
    FrameRequest f;
    std::tie(f.camera, f.pose) = camera_from([&](const char* k) { return param(req, k); });
    const std::string mode = req.has_param("mode") ? req.get_param_value("mode") : "colour";
    if (mode != "colour" && mode != "instances")
      throw InputError("'mode' must be colour or instances");
    f.mode = mode == "instances" ? FrameMode::Instances : FrameMode::Colour;
    if (req.has_param("hidden") && !req.get_param_value("hidden").empty()) {
      std::stringstream in(req.get_param_value("hidden"));
      for (std::string item; std::getline(in, item, ',');) {
        const double id = number("hidden", item);
        if (id != std::floor(id) || std::abs(id) > 1e6)
          throw InputError("'hidden' must list instance ids");
        f.hidden.push_back(static_cast<int>(id));
      }
    }
    res.set_content(encode(session_ref.frame(f), ".jpg"), "image/jpeg");
  });
  s.Get("/api/image", [&session_ref](const httplib::Request& req, httplib::Response& res) {
    const View& v = session_ref.scene().capture.views[view_index(req, session_ref.scene().capture)];
    if (!v.rgb.present()) throw InputError("view " + v.name + " has no photo");
    res.set_content(encode(v.rgb.load(), ".jpg"), "image/jpeg");
  });
  s.Post("/api/prompt", [&session_ref](const httplib::Request& req, httplib::Response& res) {
    const json body = body_json(req);
    if (!body.contains("camera") || !body["camera"].is_object())
      throw InputError("missing 'camera'");
    const json& cam = body["camera"];
    const auto [camera, pose] = camera_from([&](const char* k) { return json_text(cam, k); });
    Prompt p;
    p.name = "selection";
    const std::string kind = body.value("kind", "point");
    if (kind != "point" && kind != "scribble") throw InputError("'kind' must be point or scribble");
    p.kind = kind == "point" ? PromptKind::Point : PromptKind::Scribble;
    p.positive = points(body, "positive");
    p.negative = points(body, "negative");
    const double tau = body.contains("tau") ? number("tau", json_text(body, "tau")) : 0.75;
    if (!(tau > -1 && tau < 1)) throw InputError("'tau' must lie between -1 and 1");
    res.set_content(summary_json(session_ref.prompt(p, camera, pose, tau)).dump(),
                    "application/json");
  });
  s.Post("/api/query", [&session_ref](const httplib::Request& req, httplib::Response& res) {
    const json body = body_json(req);
    if (!body.contains("text") || !body["text"].is_string() ||
        body["text"].get<std::string>().empty())
      throw InputError("'text' must be a non-empty string");
    res.set_content(summary_json(session_ref.query(body["text"].get<std::string>())).dump(),
                    "application/json");
  });
  s.Post("/api/clear", [&session_ref](const httplib::Request&, httplib::Response& res) {
    session_ref.clear_selection();
    res.set_content(R"({"selected": 0})", "application/json");
  });
  s.Get("/api/selection/mask", [&session_ref](const httplib::Request& req, httplib::Response& res) {
    res.set_content(
        encode(session_ref.selection_mask(view_index(req, session_ref.scene().capture)), ".png"),
        "image/png");
  });
  s.Get("/api/gt/mask", [&session_ref](const httplib::Request& req, httplib::Response& res) {
    const Capture& capture = session_ref.scene().capture;
    const View& v = capture.views[view_index(req, capture)];
    const std::string name = param(req, "class");
    int cls = -1;
    for (const auto& [id, n] : capture.classes)
      if (n == name) cls = id;
    if (cls < 0) throw InputError("the capture has no class '" + name + "'");
    if (!v.gt_semantic.present()) throw InputError("view " + v.name + " has no ground truth");
    const cv::Mat semantic = v.gt_semantic.load();
    cv::Mat1b mask = semantic == cls;
    res.set_content(encode(mask, ".png"), "image/png");
  });
  s.Get("/api/selection.ply", [&session_ref](const httplib::Request&, httplib::Response& res) {
    const GaussianModel object = session_ref.export_selection();
    // write_ply writes files; each export gets its own, removed once read.
    static std::atomic<int> exports{0};
    const auto file =
        std::filesystem::temp_directory_path() /
        ("gslift-view-" + std::to_string(::getpid()) + "-" + std::to_string(exports++) + ".ply");
    write_ply(object, file);
    std::ifstream in(file, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::filesystem::remove(file);
    res.set_header("Content-Disposition", "attachment; filename=\"selection.ply\"");
    res.set_content(bytes, "application/octet-stream");
  });
}

ViewServer::~ViewServer() = default;

int ViewServer::bind(const std::string& host, int port) {
  const int bound = port == 0 ? impl_->server.bind_to_any_port(host.c_str())
                              : (impl_->server.bind_to_port(host.c_str(), port) ? port : -1);
  if (bound <= 0)
    throw InputError("cannot listen on " + host + ":" + std::to_string(port) +
                     " (in use, or not an address of this machine)");
  if (impl_->socket >= 0) ::listen(impl_->socket, kListenBacklog);
  return bound;
}

void ViewServer::serve() {
  impl_->serving = true;
  if (!impl_->stop_requested) impl_->server.listen_after_bind();
  impl_->returned = true;
}

void ViewServer::stop() {
  impl_->stop_requested = true;
  while (impl_->serving && !impl_->returned && !impl_->server.is_running())
    std::this_thread::yield();
  impl_->server.stop();
}

}  // namespace gslift
