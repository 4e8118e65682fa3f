#include "nodes/text/table_text_encoder.hpp"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "base/normalise_text.hpp"

namespace gslift {
namespace {

void add_entry(std::map<std::string, Eigen::VectorXf>& table, int& dim, const std::string& where,
               const std::string& label, const std::vector<float>& values) {
  const std::string key = normalise_text(label);
  if (key.empty()) throw InputError(where + ": empty label");
  if (values.empty()) throw InputError(where + ": '" + label + "' has no values");
  if (dim == 0) dim = static_cast<int>(values.size());
  if (static_cast<int>(values.size()) != dim)
    throw InputError(where + ": '" + label + "' has " + std::to_string(values.size()) +
                     " values, earlier entries have " + std::to_string(dim));
  Eigen::VectorXf v = Eigen::Map<const Eigen::VectorXf>(values.data(), dim);
  if (!v.allFinite() || v.norm() == 0)
    throw InputError(where + ": '" + label + "' is zero or not finite");
  if (!table.emplace(key, v / v.norm()).second)
    throw InputError(where + ": '" + label + "' appears twice");
}

void load_text(std::istream& in, const std::string& file,
               std::map<std::string, Eigen::VectorXf>& table, int& dim) {
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    const std::string where = file + ":" + std::to_string(number);
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) throw InputError(where + ": expected \"label<TAB>v1 v2 ... vD\"");
    std::vector<float> values;
    std::istringstream fields(line.substr(tab + 1));
    std::string field;
    while (fields >> field) {
      char* end = nullptr;
      errno = 0;
      const float value = std::strtof(field.c_str(), &end);
      if (end == field.c_str() || *end != '\0' || errno == ERANGE)
        throw InputError(where + ": '" + field + "' is not a number");
      values.push_back(value);
    }
    add_entry(table, dim, where, line.substr(0, tab), values);
  }
}

void load_json(std::istream& in, const std::string& file,
               std::map<std::string, Eigen::VectorXf>& table, int& dim) {
  nlohmann::json doc;
  try {
    doc = parse_json(
        std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(file + ": " + e.what());
  }
  if (!doc.is_object()) throw InputError(file + ": expected an object {\"label\": [values]}");
  for (const auto& [label, array] : doc.items()) {
    const std::string where = file + ": entry '" + label + "'";
    if (!array.is_array()) throw InputError(where + ": expected a list of numbers");
    std::vector<float> values;
    for (const auto& x : array) {
      if (!x.is_number()) throw InputError(where + ": " + x.dump() + " is not a number");
      values.push_back(x.get<float>());
    }
    add_entry(table, dim, file, label, values);
  }
}

}  // namespace

TableTextEncoder TableTextEncoder::load(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot read the embedding table");
  TableTextEncoder encoder;
  encoder.source_ = path.string();
  if (path.extension() == ".json")
    load_json(in, encoder.source_, encoder.table_, encoder.dim_);
  else
    load_text(in, encoder.source_, encoder.table_, encoder.dim_);
  if (encoder.table_.empty()) throw InputError(encoder.source_ + ": no embeddings");
  return encoder;
}

bool TableTextEncoder::contains(const std::string& text) const {
  return table_.count(normalise_text(text)) != 0;
}

std::vector<std::string> TableTextEncoder::labels() const {
  std::vector<std::string> out;
  for (const auto& kv : table_) out.push_back(kv.first);
  return out;
}

Eigen::VectorXf TableTextEncoder::encode(const std::string& text) const {
  const auto it = table_.find(normalise_text(text));
  if (it != table_.end()) return it->second;
  std::string known;
  for (const auto& kv : table_) known += (known.empty() ? "" : ", ") + ("'" + kv.first + "'");
  throw InputError(source_ + ": no embedding for '" + text + "'; known entries: " + known);
}

}  // namespace gslift
