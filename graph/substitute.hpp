// ${name} substitution in node param values. Sources: LoadOptions::vars (command line) first,
// then the graph's `params:`. A value that is exactly "${name}" becomes the source's YAML value,
// so a number, bool or list keeps its type; inside longer text the source's text is inserted and
// the result is a string. "$${" writes a literal "${". Graph params are not themselves expanded.
// A value that starts with ${name} takes the folder its relative paths are resolved against
// (DocValue::dir) from its source: none for a command-line var, the file's for a graph param.
#pragma once

#include <map>
#include <string>

#include "graph/diagnostics.hpp"
#include "graph/graph_document.hpp"

namespace gslift {

// Substitutes in every node param value of `doc` (list elements included). Errors:
// `unknown-var` (no such var or graph param), `bad-substitution` (malformed "${", or a list
// inserted into text).
void substitute_vars(GraphDocument& doc, const std::map<std::string, std::string>& vars,
                     Diagnostics& diagnostics);

}  // namespace gslift
