#include "nodes/text/register.hpp"

#include <memory>

#include "nodes/text/hashing_text_encoder.hpp"
#include "nodes/text/table_text_encoder.hpp"

namespace gslift {

void register_text_nodes(Registry& registry) {
  NodeSpec spec{
      "text.encoder",
      "the text encoder that labels and queries share (built-in hashing, or a table file)",
      {},
      {{"encoder", "TextEncoder", "encodes text to an L2-normalised vector"}},
      {string_param("kind", "hashing",
                    "hashing: built-in subword hashing; table: precomputed embeddings from `table`",
                    {"hashing", "table"}),
       int_param("dim", 384, "hashing: embedding width", 1, 65536),
       string_param("table", "",
                    "table: file of 'label<TAB>v1 .. vD' lines or a JSON {label: [..]} object")}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    std::shared_ptr<const TextEncoder> encoder;
    if (ctx.param_string("kind") == "table") {
      if (ctx.param_string("table").empty())
        throw InputError("text.encoder: kind 'table' needs the param 'table' (a file)");
      encoder = std::make_shared<const TableTextEncoder>(
          TableTextEncoder::load(ctx.param_string("table")));
    } else {
      encoder = std::make_shared<const HashingTextEncoder>(static_cast<int>(ctx.param_int("dim")));
    }
    ctx.record("encoder", encoder->name());
    ctx.record("dim", static_cast<double>(encoder->dim()));
    ctx.output<TextEncoder>("encoder", encoder);
  });
}

}  // namespace gslift
