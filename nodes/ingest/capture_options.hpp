// How a capture is read, shared by every capture format reader and the ingest.capture node.
#pragma once

#include "param/param_table.hpp"

namespace gslift {

// The largest CaptureOptions::downscale: beyond it a view of any real capture shrinks to a few
// pixels, and every prompt or training step on it fails.
constexpr int kMaxDownscale = 64;

struct CaptureOptions {
  // Hold out every n-th view (index % n == 0, the NeRF/LLFF protocol) when the capture does not
  // name its test views (capture.yaml held_out). 0 = no held-out views.
  int holdout_every = 0;
  // COLMAP models: an image listed in the model but absent from the images folder is an error
  // by default (a broken capture); with this set it is skipped with a warning (DTU scan 24 here
  // ships only the even views of its 49). NeRF transforms.json frames without an image are
  // always skipped with a warning, as instant-ngp does.
  bool skip_missing_images = false;
  // Integer downscale factor applied when images are loaded (area filter for RGB, nearest for
  // depth and label maps); intrinsics are scaled to match (Camera::scaled). 1 to kMaxDownscale.
  int downscale = 1;
  // Undistort images of cameras with distortion coefficients when they are loaded (bilinear for
  // RGB, nearest for depth and label maps; pixels mapped from outside the image are 0) and give
  // the view the same camera without distortion, so every later stage sees an ideal pinhole
  // (camera.hpp). Off: images stay as captured and Camera::distortion is kept.
  bool undistort = true;
  // With undistort: crop each undistorted image to the rectangle whose pixels all come from inside
  // the captured image (COLMAP's image_undistorter does the same), shifting the principal point.
  // Off: the captured size, with 1-3 black pixels along the border of a radially distorted
  // camera; on DTU scan 24 those cost about 1 dB of held-out PSNR (bench/splat_recon).
  bool undistort_crop = true;
  // A capture is untrusted (docs/security.md): file and folder names read from its files
  // (images.txt / images.bin, transforms.json, capture.yaml) must stay inside the capture's
  // folders, so `../../etc/passwd`, absolute paths and symlinks that leave it are refused. Set
  // for a capture you trust whose files really live elsewhere.
  bool allow_outside_paths = false;
  // Train on every n-th view alone (index % n == 0, in the capture's view order): the others are
  // held out as well, so they stay there to be scored but nothing trains on them (issue 28's DTU
  // test setting, a third of the photos: 3). 1 = every view trains (the held-out views aside).
  int train_every = 1;
};

// The params of ingest.capture that shape the reading: one entry per field above.
const ParamTable<CaptureOptions>& capture_param_table();

}  // namespace gslift
