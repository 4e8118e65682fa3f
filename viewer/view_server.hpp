// The HTTP side of `gslift view` (cpp-httplib, Debian's libcpp-httplib-dev: one header, a thread
// pool, HTTP/1.1 parsing that answers malformed requests with 400 itself). It serves the page and
// its script, embedded in the binary (viewer_page.hpp), and a JSON / image API over one
// ViewSession; it reads no file on request, so nothing outside the opened run can be served.
//
//   GET  /                          the page
//   GET  /api/info                  views (cameras), instances (label, colour), what is available
//   GET  /api/frame?CAMERA&mode=colour|instances&hidden=1,4   JPEG of the scene
//   GET  /api/image?view=I          the capture's photo of view I (JPEG)
//   POST /api/prompt                {"camera": CAMERA, "kind": "point"|"scribble",
//                                    "positive": [[x, y], ...], "negative": [...], "tau": T}
//   POST /api/query                 {"text": "..."}
//   POST /api/clear                 drops the selection
//   GET  /api/selection/mask?view=I PNG, 255 = the selection in capture view I
//   GET  /api/gt/mask?view=I&class=NAME   PNG, 255 = ground truth of class NAME in view I
//   GET  /api/selection.ply         the selection, filtered (ViewSession::export_selection)
// CAMERA: w, h, fx, fy, cx, cy, R (9 numbers, row-major world -> camera), t (3 numbers); as query
// parameters or as a JSON object. A request the API cannot read gets 400 and a JSON "error".
#pragma once

#include <memory>
#include <string>

#include "viewer/view_session.hpp"

namespace gslift {

class ViewServer {
 public:
  explicit ViewServer(ViewSession& session);
  ~ViewServer();

  // Binds host:port (0: a free port the system picks) and returns the port. Throws InputError
  // when it cannot bind.
  int bind(const std::string& host, int port);
  // Answers requests until stop() (from another thread or a signal handler's thread).
  void serve();
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gslift
