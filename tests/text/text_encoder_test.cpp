#include <cmath>

#include "base/hash.hpp"
#include "nodes/text/hashing_text_encoder.hpp"
#include "nodes/text/table_text_encoder.hpp"
#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("hashing encoder: normalised, deterministic, identical strings -> cosine 1") {
  const HashingTextEncoder enc;
  CHECK(enc.dim() == 384);
  const auto a = enc.encode("head surgeon");
  CHECK(a.norm() == Approx(1.0f));
  CHECK(cosine(a, enc.encode("head surgeon")) == Approx(1.0f));
  CHECK(cosine(a, enc.encode("  Head   SURGEON ")) == Approx(1.0f));  // case, spacing
  CHECK((a.array() == HashingTextEncoder().encode("head surgeon").array()).all());
  CHECK(enc.encode("!!").norm() == 0.0f);
}

TEST_CASE("hashing encoder: spelling variants closer than unrelated words") {
  const HashingTextEncoder enc;
  const auto us = enc.encode("anesthesia machine");
  const float variant = cosine(us, enc.encode("anaesthesia machine"));
  const float unrelated = cosine(us, enc.encode("surgeon"));
  CHECK(variant > 0.6f);
  CHECK(variant > unrelated + 0.4f);
  // Sharing a word beats sharing none.
  CHECK(cosine(enc.encode("instrument table"), enc.encode("secondary table")) >
        cosine(enc.encode("instrument table"), enc.encode("surgical lamp")));
}

TEST_CASE("hashing encoder: one word's features by hand") {
  // "ab" -> features "w:ab" and the 3-grams of "<ab>": "<ab", "ab>"; no 4- or 5-gram fits
  // except "<ab>" (4). Four features of weight +-1: the norm before normalisation is 2 unless two
  // collide, so every non-zero entry is +-0.5 here.
  const HashingTextEncoder enc(1 << 16);
  const auto v = enc.encode("ab");
  int nonzero = 0;
  for (int i = 0; i < v.size(); ++i)
    if (v[i] != 0) {
      ++nonzero;
      CHECK(std::abs(v[i]) == Approx(0.5f));
    }
  CHECK(nonzero == 4);
  const uint64_t h = fnv1a64("w:ab");
  CHECK(v[h % (1 << 16)] == ((h >> 63) ? -0.5f : 0.5f));
}

TEST_CASE("table encoder loads text and JSON tables alike") {
  for (const char* file : {"text/table.tsv", "text/table.json"}) {
    const auto enc = TableTextEncoder::load(test::test_data(file));
    CHECK(enc.dim() == 4);
    CHECK(enc.labels() == std::vector<std::string>{"head surgeon", "monitor"});
    const auto v = enc.encode("Head Surgeon");
    const float n = std::sqrt(0.01f + 0.04f + 0.09f + 0.16f);
    CHECK(v[3] == Approx(0.4f / n));
    CHECK(v.norm() == Approx(1.0f));
    CHECK(cosine(enc.encode("monitor"), enc.encode("MONITOR")) == Approx(1.0f));
    CHECK_THROWS_WITH(enc.encode("lamp"), Catch::Contains("no embedding for 'lamp'") &&
                                              Catch::Contains("'head surgeon', 'monitor'"));
  }
}

TEST_CASE("table encoder errors name the file and line") {
  CHECK_THROWS_WITH(TableTextEncoder::load(test::test_data("text/bad_dims.tsv")),
                    Catch::Contains("bad_dims.tsv:2") && Catch::Contains("has 2 values"));
  CHECK_THROWS_WITH(TableTextEncoder::load(test::test_data("text/bad_number.tsv")),
                    Catch::Contains("bad_number.tsv:1") && Catch::Contains("'x3'"));
  CHECK_THROWS_AS(TableTextEncoder::load(test::test_data("text/missing.tsv")), InputError);
}
