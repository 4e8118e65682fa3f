#include "nodes/text/register.hpp"

#include <memory>

#include "nodes/text/hashing_text_encoder.hpp"
#include "nodes/text/table_text_encoder.hpp"

namespace gslift {
namespace {

enum class TextEncoderKind { Hashing, Table };

// text.encoder's params: which encoder, and what it needs.
struct TextEncoderParams {
  TextEncoderKind kind = TextEncoderKind::Hashing;
  int dim = 384;      // hashing
  std::string table;  // table: the embeddings file
};

const ParamTable<TextEncoderParams>& text_encoder_param_table() {
  using P = TextEncoderParams;
  static const EnumNames<TextEncoderKind> kinds = {{TextEncoderKind::Hashing, "hashing"},
                                                   {TextEncoderKind::Table, "table"}};
  static const ParamTable<P> table =
      ParamTable<P>()
          .add("kind", &P::kind, kinds,
               "hashing: built-in subword hashing; table: precomputed embeddings from `table`")
          .add("dim", &P::dim, "hashing: embedding width", 1, 65536)
          .add("table", &P::table,
               "table: file of 'label<TAB>v1 .. vD' lines or a JSON {label: [..]} object")
          .path();
  return table;
}

void run_text_encoder(NodeContext& ctx, const TextEncoderParams& p) {
  std::shared_ptr<const TextEncoder> encoder;
  if (p.kind == TextEncoderKind::Table) {
    if (p.table.empty())
      throw InputError("text.encoder: kind 'table' needs the param 'table' (a file)");
    encoder = std::make_shared<const TableTextEncoder>(TableTextEncoder::load(p.table));
  } else {
    encoder = std::make_shared<const HashingTextEncoder>(p.dim);
  }
  ctx.record("encoder", encoder->name());
  ctx.record("dim", static_cast<double>(encoder->dim()));
  ctx.output<TextEncoder>("encoder", encoder);
}

}  // namespace

void register_text_nodes(Registry& registry) {
  NodeSpec spec{
      "text.encoder",
      "the text encoder that labels and queries share (built-in hashing, or a table file)",
      {},
      {{"encoder", "TextEncoder", "encodes text to an L2-normalised vector"}}};
  registry.add(std::move(spec), text_encoder_param_table(), run_text_encoder);
}

}  // namespace gslift
