// Small generic node types that exercise the runtime without any 3D vision, registered only in
// the tests' own Registry, and a helper to build Graphs directly (as the loader would).
#pragma once

#include <map>
#include <string>
#include <utility>

#include "graph/graph.hpp"
#include "runtime/registry.hpp"

namespace gslift::test {

struct Number {
  double value = 0;
};
// Its binary form for the stage cache (the registry's add_codec finds these).
void write(ByteWriter& w, const Number& n);
void read(ByteReader& r, Number& n);

}  // namespace gslift::test

namespace gslift {
GSLIFT_PORT_TYPE(test::Number, "Number");
}

namespace gslift::test {

// debug.constant  params value            -> out:Number = value
// debug.sleep     params ms, write; in? in:Number -> out:Number = in (or 0); sleeps in 5 ms
//                 steps, reporting progress and throwing Cancelled as soon as ctx.cancelled()
//                 (both at least once, even for ms 0); with write, first writes
//                 <out_dir>/partial.txt
// debug.fail      params kind (input|other), message; in? in:Number -> throws InputError or
//                 std::runtime_error
// debug.random    -> out:Number = first uniform of RandomStream(ctx.seed()) in [0,1); records
//                 "seed" (as a string, exact) and "draw"
// debug.add       in a:Number, b:Number -> out:Number = a + b
// debug.lazy      declares out:Number but never sets it
// debug.wrong     sets out:Number with a value of another type (std::string)
// debug.write     writes <out_dir>/input.txt with ctx.run_input(); fails (InputError) when the
//                 input contains "bad" -> out:Number = 1
// Number has a binary form (add_codec), so these nodes go through the stage cache like real ones.
Registry debug_registry();

// A GraphNode with every param of its type at the spec default, then `params` applied (the loader
// does this for real graphs); `line` is its YAML line in file "test.yaml".
GraphNode debug_node(const Registry& registry, const std::string& id, const std::string& type,
                     std::map<std::string, PortRef> inputs = {},
                     std::map<std::string, ParamValue> params = {}, int line = 0);

}  // namespace gslift::test
