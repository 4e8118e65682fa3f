#include "nodes/ingest/capture_inventory.hpp"

#include <fstream>

#include "nodes/ingest/capture_loader.hpp"
#include "tests/ingest/small_capture.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

TEST_CASE("the inventory says what a capture holds and where it looked for the rest",
          "[ingest][preflight]") {
  // The small capture: 3 views with images, depth, gt/instance and gt/classes.yaml, no
  // gt/semantic, no VLM replies, no SAM masks; cam_02 held out.
  const fs::path dir = test::write_small_capture("inventory", "held_out: [cam_02]\n");
  CaptureInventory inv = capture_inventory(load_capture(dir));
  CHECK(inv[CaptureItem::Images].present);
  CHECK(inv[CaptureItem::Depth].present);
  CHECK(inv[CaptureItem::GtInstances].present);
  CHECK(inv[CaptureItem::GtClasses].present);
  CHECK(inv[CaptureItem::HeldOutViews].present);
  CHECK_FALSE(inv[CaptureItem::GtSemantics].present);
  CHECK(inv[CaptureItem::GtSemantics].looked_for ==
        (dir / "gt" / "").string() + "semantic/<view>.png");
  CHECK_FALSE(inv[CaptureItem::VlmReplies].present);
  CHECK(inv[CaptureItem::VlmReplies].looked_for ==
        (dir / "vlm" / "").string() + "<view>/round_0.txt (none for any of the 3 views)");
  CHECK(inv[CaptureItem::VlmReplies].produced_by.find("vlm.query") != std::string::npos);
  CHECK_FALSE(inv[CaptureItem::SamAutoMasks].present);

  // One view's reply and one view's automatic masks are enough: the others found nothing.
  fs::create_directories(dir / "vlm/cam_01");
  std::ofstream(dir / "vlm/cam_01/round_0.txt") << "[]";
  fs::create_directories(dir / "sam_auto");
  std::ofstream(dir / "sam_auto/cam_00.json") << "[]";
  inv = capture_inventory(load_capture(dir));
  CHECK(inv[CaptureItem::VlmReplies].present);
  CHECK(inv[CaptureItem::SamAutoMasks].present);
}

TEST_CASE("a capture without held-out views or ground truth says how to get them",
          "[ingest][preflight]") {
  const fs::path dir = test::write_small_capture("inventory_plain", "");
  fs::remove_all(dir / "gt");
  std::ofstream(dir / "capture.yaml", std::ios::trunc)
      << "format: gslift.capture/v1\nname: small\nmodel: sparse/0\nimages: images\n";
  CaptureInventory inv = capture_inventory(load_capture(dir));
  CHECK_FALSE(inv[CaptureItem::Depth].present);
  CHECK(inv[CaptureItem::Depth].looked_for.find("this capture names none") != std::string::npos);
  CHECK_FALSE(inv[CaptureItem::HeldOutViews].present);
  CHECK(inv[CaptureItem::HeldOutViews].produced_by.find("holdout_every=8") != std::string::npos);
  CHECK_FALSE(inv[CaptureItem::GtClasses].present);
  CHECK(inv[CaptureItem::GtClasses].looked_for.find("names none") != std::string::npos);
  CHECK(inv[CaptureItem::GtClasses].produced_by.find("production form") != std::string::npos);
  // holdout_every makes held-out views of a capture that names none.
  CaptureOptions every_second;
  every_second.holdout_every = 2;
  CHECK(capture_inventory(load_capture(dir, every_second))[CaptureItem::HeldOutViews].present);
}
