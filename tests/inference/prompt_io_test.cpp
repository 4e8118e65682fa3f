// Prompt files in JSON and YAML, and the InputErrors that bad ones get (naming file and field).
#include "nodes/inference/prompt_io.hpp"

#include <fstream>

#include "base/errors.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return dir / name;
}

// The InputError message of reading `file`; empty when it reads.
std::string error_of(const fs::path& file) {
  try {
    read_prompt_file(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("prompt files in YAML and JSON read the same prompts") {
  const fs::path dir = test::scratch_dir("prompt_io");
  const PromptSet yaml = read_prompt_file(write(dir, "p.yaml", R"(prompts:
  - {name: cup, view: 000000, positive: [[10, 20], [11.7, 21]], negative: [[3, 4]]}
  - name: table
    kind: scribble
    view: cam_01
    positive: [[1, 2], [30, 2]]
)"));
  const PromptSet json = read_prompt_file(write(dir, "p.json", R"([
  {"name": "cup", "view": "000000", "positive": [[10, 20], [11.7, 21]], "negative": [[3, 4]]},
  {"name": "table", "kind": "scribble", "view": "cam_01", "positive": [[1, 2], [30, 2]]}])"));
  REQUIRE(yaml.prompts.size() == 2);
  REQUIRE(json.prompts.size() == 2);
  for (size_t k = 0; k < 2; ++k) {
    CHECK(yaml.prompts[k].name == json.prompts[k].name);
    CHECK(yaml.prompts[k].view == json.prompts[k].view);
    CHECK(yaml.prompts[k].kind == json.prompts[k].kind);
    CHECK(yaml.prompts[k].positive == json.prompts[k].positive);
    CHECK(yaml.prompts[k].negative == json.prompts[k].negative);
  }
  CHECK(yaml.prompts[0].view == "000000");  // the leading zero keeps it a string
  CHECK(yaml.prompts[0].kind == PromptKind::Point);
  CHECK(yaml.prompts[0].positive[1] == cv::Point(11, 21));
  CHECK(yaml.prompts[1].kind == PromptKind::Scribble);
}

TEST_CASE("bad prompt files are InputErrors naming the file and the field") {
  const fs::path dir = test::scratch_dir("prompt_io_bad");
  struct Case {
    std::string name, text, field;
  };
  const std::vector<Case> cases = {
      {"typo.yaml", "- {view: a, postive: [[1, 2]]}", "'postive'"},
      {"name.json", R"([{"view": "a", "name": 3, "positive": [[1, 2]]}])", "'name'"},
      {"noview.yaml", "- {positive: [[1, 2]]}", "\"view\""},
      {"pixel.yaml", "- {view: a, positive: [[1, 2, 3]]}", "'positive'"},
      {"kind.json", R"([{"view": "a", "kind": "lasso", "positive": [[1, 2]]}])", "lasso"},
      {"mask.yaml", "- {view: a, kind: mask}", "\"mask\""},
      {"nomask.yaml", "- {view: a, mask: missing.png}", "missing.png"},
      {"broken.yaml", "- {view: a, positive: [[1, 2]", "not YAML"},
      {"broken.json", "[{\"view\": ", "not JSON"},
      {"scalar.yaml", "hello", "list of prompts"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(write(dir, c.name, c.text));
    INFO(c.name << ": " << e);
    CHECK(e.find(c.name) != std::string::npos);
    CHECK(e.find(c.field) != std::string::npos);
  }
  CHECK(error_of(dir / "absent.yaml").find("absent.yaml") != std::string::npos);
}
