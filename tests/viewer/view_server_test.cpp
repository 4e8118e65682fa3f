// gslift view's server in process, over a hand-made two-blob scene (tests/inference/
// query_scene.hpp): the page and the API answer, a click selects the blob under it, a text query
// its instance, the export is a PLY of that blob, bad requests get 400 while the server goes on,
// no file outside the scene is served, and 1000 clients at once are all answered.
#include "viewer/view_server.hpp"

#include <atomic>
#include <thread>

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "nodes/text/hashing_text_encoder.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using nlohmann::json;

namespace {

// Left blob: instance 0 "chair", feature e1; right blob: instance 1 "table", feature e2.
ViewScene two_blob_scene() {
  ViewScene s;
  s.title = "two blobs";
  s.model = test::two_blobs();
  s.model.sh_degree = 0;
  s.model.sh = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
  s.model.feature_dim = 2;
  s.model.features = {1, 0, 0, 1};
  View v;
  v.name = "v0";
  v.camera = test::query_camera();
  s.capture.views.push_back(v);
  s.instance_labels = {"chair", "table"};
  s.encoder = std::make_shared<HashingTextEncoder>(64);
  return s;
}

// The server on a free port of 127.0.0.1, answering on its own thread until destroyed.
struct RunningServer {
  ViewSession session{two_blob_scene()};
  ViewServer server{session};
  int port = server.bind("127.0.0.1", 0);
  std::thread thread{[this] { server.serve(); }};
  ~RunningServer() {
    server.stop();
    thread.join();
  }
  httplib::Client client() const { return httplib::Client("127.0.0.1", port); }
};

const char* const kCamera = "w=64&h=48&fx=60&fy=60&cx=32&cy=24&R=1,0,0,0,1,0,0,0,1&t=0,0,0";

json camera_json() {
  return {{"w", 64},
          {"h", 48},
          {"fx", 60},
          {"fy", 60},
          {"cx", 32},
          {"cy", 24},
          {"R", {1, 0, 0, 0, 1, 0, 0, 0, 1}},
          {"t", {0, 0, 0}}};
}

cv::Mat decode(const std::string& bytes, int flags) {
  return cv::imdecode(std::vector<uchar>(bytes.begin(), bytes.end()), flags);
}

}  // namespace

TEST_CASE("the viewer serves its page, frames, prompts, queries and the export", "[viewer]") {
  RunningServer s;
  httplib::Client c = s.client();
  auto page = c.Get("/");
  REQUIRE(page);
  CHECK(page->status == 200);
  CHECK(page->body.find("<canvas id=\"frame\"") != std::string::npos);
  // Nothing the page uses comes from elsewhere.
  CHECK(page->body.find("http://") == std::string::npos);
  CHECK(page->body.find("https://") == std::string::npos);

  auto info = c.Get("/api/info");
  REQUIRE(info);
  const json i = json::parse(info->body);
  CHECK(i["views"].size() == 1);
  CHECK(i["instances"].size() == 2);
  CHECK(i["instances"][1]["label"] == "table");
  CHECK(i["features"] == true);

  auto frame = c.Get(std::string("/api/frame?") + kCamera + "&mode=instances");
  REQUIRE(frame);
  REQUIRE(frame->status == 200);
  const cv::Mat3b rgb = decode(frame->body, cv::IMREAD_COLOR);
  REQUIRE(rgb.cols == 64);
  REQUIRE(rgb.rows == 48);
  // Each blob in its instance's colour (BGR here), the corner the dark background.
  const cv::Vec3b left = ViewSession::instance_colour(0), right = ViewSession::instance_colour(1);
  CHECK(cv::norm(cv::Vec3d(rgb(24, 17)) - cv::Vec3d(left[2], left[1], left[0])) < 25);
  CHECK(cv::norm(cv::Vec3d(rgb(24, 47)) - cv::Vec3d(right[2], right[1], right[0])) < 25);
  CHECK(cv::norm(cv::Vec3d(rgb(1, 1)) - cv::Vec3d(36, 31, 31)) < 12);
  // Hidden instance 1: its blob is gone.
  auto hidden = c.Get(std::string("/api/frame?") + kCamera + "&mode=instances&hidden=1");
  REQUIRE(hidden);
  CHECK(cv::norm(cv::Vec3d(decode(hidden->body, cv::IMREAD_COLOR).at<cv::Vec3b>(24, 47)) -
                 cv::Vec3d(36, 31, 31)) < 12);

  // A click on the left blob selects it (cos 1 with e1, 0 with e2).
  json prompt = {{"camera", camera_json()}, {"positive", {{17, 24}}}, {"tau", 0.75}};
  auto r = c.Post("/api/prompt", prompt.dump(), "application/json");
  REQUIRE(r);
  REQUIRE(r->status == 200);
  CHECK(json::parse(r->body)["selected"] == 1);
  auto mask = c.Get("/api/selection/mask?view=0");
  REQUIRE(mask);
  const cv::Mat1b m = decode(mask->body, cv::IMREAD_GRAYSCALE);
  CHECK(m(24, 17) == 255);
  CHECK(m(24, 47) == 0);
  auto ply = c.Get("/api/selection.ply");
  REQUIRE(ply);
  CHECK(ply->status == 200);
  CHECK(ply->body.rfind("ply\n", 0) == 0);
  CHECK(ply->body.find("element vertex 1\n") != std::string::npos);

  // The text query "table" lands on instance 1.
  r = c.Post("/api/query", R"({"text": "table"})", "application/json");
  REQUIRE(r);
  REQUIRE(r->status == 200);
  CHECK(json::parse(r->body)["instances"] == json::array({1}));
  const cv::Mat1b q = decode(c.Get("/api/selection/mask?view=0")->body, cv::IMREAD_GRAYSCALE);
  CHECK(q(24, 47) == 255);
  CHECK(q(24, 17) == 0);
  r = c.Post("/api/clear", "{}", "application/json");
  CHECK(s.session.selected_count() == 0);
  CHECK(c.Get("/api/selection.ply")->status == 400);  // nothing to export
}

TEST_CASE("bad requests get 400, files are never served, the server goes on", "[viewer]") {
  RunningServer s;
  httplib::Client c = s.client();
  for (const std::string& bad : std::vector<std::string>{
           "/api/frame?w=abc", "/api/frame?w=64&h=48&fx=60&fy=60&cx=32&cy=24&R=1,0&t=0,0,0",
           std::string("/api/frame?") + kCamera + "&mode=x", "/api/image?view=../../etc/passwd",
           "/api/image?view=7", "/api/selection/mask?view=-1", "/api/gt/mask?view=0&class=x"}) {
    auto r = c.Get(bad.c_str());
    INFO(bad);
    REQUIRE(r);
    CHECK(r->status == 400);
    CHECK(json::parse(r->body).contains("error"));
  }
  for (const char* body : {"not json", "[1]", R"({"camera": 1})", R"({"text": 3})"}) {
    INFO(body);
    CHECK(c.Post("/api/prompt", body, "application/json")->status == 400);
    CHECK(c.Post("/api/query", body, "application/json")->status == 400);
  }
  // A prompt outside the frame is the prompt's error, not the server's.
  json prompt = {{"camera", camera_json()}, {"positive", {{64, 24}}}};
  CHECK(c.Post("/api/prompt", prompt.dump(), "application/json")->status == 400);
  for (const char* path : {"/../../../../etc/passwd", "/etc/passwd", "/viewer.html", "/api"})
    CHECK(c.Get(path)->status == 404);
  // Malformed HTTP on a raw socket: httplib answers 400 (414 for a request line past its limit)
  // and closes.
  for (const auto& [raw, status] : std::vector<std::pair<std::string, std::string>>{
           {"GARBAGE\r\n\r\n", "400"},
           {"GET /\r\n\r\n", "400"},
           {std::string(20000, 'A') + "\r\n\r\n", "414"}}) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(s.port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
    REQUIRE(::send(fd, raw.data(), raw.size(), MSG_NOSIGNAL) > 0);
    char reply[64] = {};
    const ssize_t n = ::recv(fd, reply, sizeof reply - 1, 0);
    ::close(fd);
    INFO(raw.substr(0, 40));
    CHECK(n > 0);
    CHECK(std::string(reply).rfind("HTTP/1.1 " + status, 0) == 0);
  }
  CHECK(c.Get("/api/info")->status == 200);
}

TEST_CASE("1000 clients at once are all answered", "[viewer]") {
  RunningServer s;
  constexpr int kClients = 1000;
  std::atomic<int> ok{0}, failed{0};
  std::atomic<bool> go{false};
  std::vector<std::thread> clients;
  for (int k = 0; k < kClients; ++k)
    clients.emplace_back([&, k] {
      while (!go) std::this_thread::yield();
      httplib::Client c("127.0.0.1", s.port);
      c.set_connection_timeout(30);
      c.set_read_timeout(60);
      // Every fourth asks for a frame (the rasterizer behind the session's lock), one in ten is
      // malformed; each must get its own answer.
      const std::string path = k % 10 == 0  ? "/api/frame?w=1"
                               : k % 4 == 0 ? std::string("/api/frame?") + kCamera
                                            : "/api/info";
      auto r = c.Get(path.c_str());
      const int expected = k % 10 == 0 ? 400 : 200;
      (r && r->status == expected ? ok : failed)++;
    });
  go = true;
  for (auto& t : clients) t.join();
  CHECK(ok == kClients);
  CHECK(failed == 0);
  CHECK(s.client().Get("/api/info")->status == 200);
}
