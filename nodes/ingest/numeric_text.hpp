// Locale-independent parsing of numbers in the text formats ingest reads (COLMAP text models,
// trajectory and intrinsics files). A field that is not a number is an InputError naming the
// file and line, never a silent 0 as with atof.
#pragma once

#include <string>
#include <vector>

namespace gslift {

// Splits on whitespace.
std::vector<std::string> split_whitespace(const std::string& line);

// Parses a whole token as a number; `where` ("file:line") and `what` ("QW") name it in errors.
double parse_double(const std::string& token, const std::string& where, const std::string& what);
long long parse_integer(const std::string& token, const std::string& where,
                        const std::string& what);

// Every whitespace-separated number of a text file, in order (e.g. a 4x4 pose or a 3x3 K).
std::vector<double> read_numbers_file(const std::string& path);

}  // namespace gslift
