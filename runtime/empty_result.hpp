// An empty result is an error, not "ok" (issue 29): a node whose output holds nothing (no VLM
// box in any view, no lifted instance) fails with the cause, so nothing downstream runs on
// nothing. Its `allow_empty` param accepts the empty output where a graph means it (a capture in
// which the objects may all be out of view).
#pragma once

#include <string>

#include "base/errors.hpp"
#include "param/param_table.hpp"

namespace gslift {

// A node's options plus its `allow_empty` param.
template <class Options>
struct EmptyAllowed {
  Options options;
  bool allow_empty = false;
};

// `table`'s params and `allow_empty`; `nothing` says what an empty output is ("no box in any
// view").
template <class Options>
ParamTable<EmptyAllowed<Options>> with_allow_empty(const ParamTable<Options>& table,
                                                   const std::string& nothing) {
  using P = EmptyAllowed<Options>;
  return ParamTable<P>()
      .nest(&P::options, table)
      .add("allow_empty", &P::allow_empty,
           "accept an output with " + nothing +
               " (otherwise the node fails, and nothing "
               "downstream runs)");
}

// Throws InputError "<node type>: <cause> (allow_empty: true accepts it)" when `empty` and the
// node does not allow it.
inline void fail_if_empty(bool empty, bool allowed, const std::string& node_type,
                          const std::string& cause) {
  if (empty && !allowed)
    throw InputError(node_type + ": " + cause +
                     "; nothing downstream would have anything to work on (set " +
                     "allow_empty: true where the graph means it)");
}

}  // namespace gslift
