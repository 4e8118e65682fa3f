#include "nodes/ingest/numeric_text.hpp"

#include <fstream>
#include <locale>
#include <sstream>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/utf8.hpp"

namespace gslift {

std::vector<std::string> split_whitespace(const std::string& line) {
  std::vector<std::string> tokens;
  std::istringstream in(line);
  std::string t;
  while (in >> t) tokens.push_back(t);
  return tokens;
}

namespace {

template <class T>
T parse_number(const std::string& token, const std::string& where, const std::string& what,
               const char* kind) {
  std::istringstream in(token);
  in.imbue(std::locale::classic());
  T v{};
  in >> v;
  if (in.fail() || in.peek() != std::char_traits<char>::eof())
    throw InputError(where + ": " + what + " must be " + kind + ", got '" + printable(token) + "'");
  return v;
}

}  // namespace

double parse_double(const std::string& token, const std::string& where, const std::string& what) {
  return parse_number<double>(token, where, what, "a number");
}

long long parse_integer(const std::string& token, const std::string& where,
                        const std::string& what) {
  return parse_number<long long>(token, where, what, "an integer");
}

std::vector<double> read_numbers_file(const std::string& path) {
  require_regular_file(path);
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  std::vector<double> values;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    for (const auto& t : split_whitespace(line))
      values.push_back(parse_double(t, path + ":" + std::to_string(n), "value"));
  return values;
}

}  // namespace gslift
