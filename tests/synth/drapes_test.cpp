// The textureless-drapes knob: which instances it covers, that it leaves everything else of the
// capture alone, and that SfM points leave the draped surfaces.
#include <set>

#include "base/input_file.hpp"
#include "nodes/ingest/colmap_model.hpp"
#include "nodes/synth/drapes.hpp"
#include "nodes/synth/or_capture.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::synth;
namespace fs = std::filesystem;

namespace {

// The instances a drape may cover: everything but the people, the patient and the lamp.
std::set<int> equipment_of(const OrScene& scene) {
  std::set<int> out;
  for (const auto& [instance, cls] : scene.instance_class)
    if (cls == kOperatingTable || cls == kAnesthesiaMachine || cls == kInstrumentTable ||
        cls == kSecondaryTable || cls == kMonitor || cls == kCArm)
      out.insert(instance);
  return out;
}

}  // namespace

TEST_CASE("drapes cover round(fraction x n) equipment instances in flat blue, nothing else") {
  OrSceneOptions o;
  o.seed = 3;
  const OrScene original = make_or_scene(o);
  const std::set<int> equipment = equipment_of(original);
  REQUIRE(equipment.size() >= 6);  // 2 tables + side table, machine, monitor(s), C-arm

  OrScene none = original;
  CHECK(drape_equipment(none, 0.0, o.seed).empty());

  OrScene all = original;
  CHECK(drape_equipment(all, 1.0, o.seed) == equipment);

  OrScene half = original;
  const std::set<int> draped = drape_equipment(half, 0.5, o.seed);
  CHECK(draped.size() == static_cast<size_t>(std::lround(0.5 * double(equipment.size()))));
  for (int id : draped) CHECK(equipment.count(id));
  OrScene again = original;
  CHECK(drape_equipment(again, 0.5, o.seed) == draped);  // deterministic for the seed

  REQUIRE(half.primitives.size() == original.primitives.size());
  for (size_t i = 0; i < original.primitives.size(); ++i) {
    const Primitive &before = original.primitives[i], &after = half.primitives[i];
    CHECK(after.centre == before.centre);
    CHECK(after.instance == before.instance);
    CHECK(none.primitives[i].material.albedo == before.material.albedo);
    if (draped.count(before.instance)) {
      CHECK(after.material.texture == Texture::Flat);
      CHECK(after.material.albedo == drape_material().albedo);
    } else {
      CHECK(after.material.albedo == before.material.albedo);
      CHECK(after.material.texture == before.material.texture);
    }
  }
  CHECK_THROWS_WITH(drape_equipment(half, 1.5, o.seed),
                    Catch::Contains("drapes must be in [0, 1]"));
}

TEST_CASE("a draped capture keeps its geometry and loses the SfM points on the drapes") {
  const fs::path dir = test::scratch_dir("synth_drapes");
  auto settings = [](const std::string& drapes) {
    return make_settings({{"width", "96"},
                          {"height", "72"},
                          {"seed", "2"},
                          {"sparse_points", "3000"},
                          {"drapes", drapes}});
  };
  write_or_capture(settings("0"), dir / "bare");
  write_or_capture(settings("1"), dir / "draped");
  const ColmapModel bare = read_colmap_text(dir / "bare" / "sparse" / "0");
  const ColmapModel draped = read_colmap_text(dir / "draped" / "sparse" / "0");
  // The same pixels are drawn; those on draped equipment give no point, every other point stays.
  REQUIRE(bare.points.size() > 1000);
  CHECK(draped.points.size() < bare.points.size() * 0.97);
  CHECK(draped.points.size() > bare.points.size() / 2);
  size_t j = 0;
  for (size_t i = 0; i < bare.points.size() && j < draped.points.size(); ++i)
    if (bare.points.xyz[i] == draped.points.xyz[j]) ++j;
  CHECK(j == draped.points.size());  // an ordered subset
  // Ground truth is unchanged; the pictures differ.
  CHECK(read_input_file(dir / "bare" / "gt" / "instance" / "cam_00.png") ==
        read_input_file(dir / "draped" / "gt" / "instance" / "cam_00.png"));
  CHECK(read_input_file(dir / "bare" / "images" / "cam_00.png") !=
        read_input_file(dir / "draped" / "images" / "cam_00.png"));
}
