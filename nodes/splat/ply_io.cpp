#include "nodes/splat/ply_io.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/utf8.hpp"

namespace gslift {
namespace {

std::vector<std::string> float_property_names(const GaussianModel& model) {
  std::vector<std::string> names = {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
  const int rest = 3 * (GaussianModel::sh_coeffs(model.sh_degree) - 1);
  for (int i = 0; i < rest; ++i) names.push_back("f_rest_" + std::to_string(i));
  names.push_back("opacity");
  for (int i = 0; i < 3; ++i) names.push_back("scale_" + std::to_string(i));
  for (int i = 0; i < 4; ++i) names.push_back("rot_" + std::to_string(i));
  for (int i = 0; i < model.feature_dim; ++i) names.push_back("feat_" + std::to_string(i));
  return names;
}

template <class T>
void append(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the machines we support are little endian
  out.append(bytes, sizeof(T));
}

enum class Scalar { I8, U8, I16, U16, I32, U32, F32, F64 };

bool parse_scalar(const std::string& name, Scalar* s) {
  static const std::map<std::string, Scalar> kTypes = {
      {"char", Scalar::I8},    {"int8", Scalar::I8},     {"uchar", Scalar::U8},
      {"uint8", Scalar::U8},   {"short", Scalar::I16},   {"int16", Scalar::I16},
      {"ushort", Scalar::U16}, {"uint16", Scalar::U16},  {"int", Scalar::I32},
      {"int32", Scalar::I32},  {"uint", Scalar::U32},    {"uint32", Scalar::U32},
      {"float", Scalar::F32},  {"float32", Scalar::F32}, {"double", Scalar::F64},
      {"float64", Scalar::F64}};
  auto it = kTypes.find(name);
  if (it == kTypes.end()) return false;
  *s = it->second;
  return true;
}

size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::I8:
    case Scalar::U8:
      return 1;
    case Scalar::I16:
    case Scalar::U16:
      return 2;
    case Scalar::I32:
    case Scalar::U32:
    case Scalar::F32:
      return 4;
    case Scalar::F64:
      return 8;
  }
  return 0;
}

template <class T>
double load_as(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

double decode(Scalar s, const char* p) {
  switch (s) {
    case Scalar::I8:
      return load_as<int8_t>(p);
    case Scalar::U8:
      return load_as<uint8_t>(p);
    case Scalar::I16:
      return load_as<int16_t>(p);
    case Scalar::U16:
      return load_as<uint16_t>(p);
    case Scalar::I32:
      return load_as<int32_t>(p);
    case Scalar::U32:
      return load_as<uint32_t>(p);
    case Scalar::F32:
      return load_as<float>(p);
    case Scalar::F64:
      return load_as<double>(p);
  }
  return 0;
}

struct Property {
  std::string name;
  Scalar type = Scalar::F32;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
  bool has_list = false;
};

// Index of the properties named prefix0, prefix1, ... (consecutive from 0), in numeric order.
std::vector<int> numbered(const std::map<std::string, int>& index, const std::string& prefix) {
  std::vector<int> out;
  for (int i = 0;; ++i) {
    auto it = index.find(prefix + std::to_string(i));
    if (it == index.end()) return out;
    out.push_back(it->second);
  }
}

// An instance or class id stored as a PLY scalar; NaN or a value beyond int32 would make the cast
// undefined.
int32_t id_value(double v, const std::string& where, size_t vertex) {
  if (!(v >= std::numeric_limits<int32_t>::min() && v <= std::numeric_limits<int32_t>::max()))
    throw InputError(where + "vertex " + std::to_string(vertex) + " has id " + std::to_string(v) +
                     ", not an int32");
  return static_cast<int32_t>(v);
}

}  // namespace

void write_ply(const GaussianModel& model, const std::filesystem::path& path) {
  const size_t n = model.size();
  const int K = GaussianModel::sh_coeffs(model.sh_degree);
  const bool ids = !model.instance_ids.empty(), classes = !model.class_ids.empty();
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\nelement vertex " << n << "\n";
  for (const auto& name : float_property_names(model)) header << "property float " << name << "\n";
  if (ids) header << "property int instance_id\n";
  if (classes) header << "property int class_id\n";
  header << "end_header\n";

  std::string bytes = header.str();
  const size_t row_bytes = 4 * (float_property_names(model).size() + ids + classes);
  bytes.reserve(bytes.size() + n * row_bytes);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) append(bytes, model.means[i * 3 + k]);
    for (int k = 0; k < 3; ++k) append(bytes, 0.f);
    const float* sh = &model.sh[i * K * 3];
    for (int c = 0; c < 3; ++c) append(bytes, sh[c]);
    for (int c = 0; c < 3; ++c)  // channel-major rest coefficients
      for (int k = 1; k < K; ++k) append(bytes, sh[k * 3 + c]);
    append(bytes, model.opacity_logits[i]);
    for (int k = 0; k < 3; ++k) append(bytes, model.log_scales[i * 3 + k]);
    for (int k = 0; k < 4; ++k) append(bytes, model.quats[i * 4 + k]);
    for (int k = 0; k < model.feature_dim; ++k)
      append(bytes, model.features[i * model.feature_dim + k]);
    if (ids) append(bytes, model.instance_ids[i]);
    if (classes) append(bytes, model.class_ids[i]);
  }
  write_file_atomically(path, bytes);
}

namespace {

struct PlyHeader {
  bool binary = false;
  std::vector<Element> elements;
};

// The header's lines up to end_header; the stream is left at the first data byte.
PlyHeader read_ply_header(std::istream& in, const std::string& where) {
  std::string line;
  if (!std::getline(in, line) || line.substr(0, 3) != "ply")
    throw InputError(where + "not a PLY file (missing 'ply' magic)");
  PlyHeader header;
  std::vector<Element>& elements = header.elements;
  for (;;) {
    if (!std::getline(in, line)) throw InputError(where + "PLY header has no end_header");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "end_header") break;
    if (key == "comment" || key == "obj_info" || key.empty()) continue;
    if (key == "format") {
      std::string format;
      words >> format;
      if (format == "binary_little_endian")
        header.binary = true;
      else if (format != "ascii")
        throw InputError(where + "unsupported PLY format '" + printable(format) +
                         "' (need binary_little_endian or ascii)");
    } else if (key == "element") {
      Element e;
      std::string count;
      words >> e.name >> count;
      // Digits only: ">> size_t" would wrap "-1" to 2^64 - 1 and read "1e10" as 1.
      if (!words || count.empty() || count.size() > 19 ||
          count.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(where + "malformed PLY line '" + printable(line) + "'");
      e.count = std::stoull(count);
      elements.push_back(e);
    } else if (key == "property") {
      if (elements.empty()) throw InputError(where + "PLY property before any element");
      std::string type, name;
      words >> type;
      if (type == "list") {
        elements.back().has_list = true;
        continue;
      }
      words >> name;
      Property p{name};
      if (!parse_scalar(type, &p.type))
        throw InputError(where + "unknown PLY property type '" + printable(type) + "'");
      elements.back().properties.push_back(p);
    } else {
      throw InputError(where + "unexpected PLY header line '" + printable(line) + "'");
    }
  }
  if (elements.empty() || elements.front().name != "vertex")
    throw InputError(where + "the first PLY element must be 'vertex'");
  if (elements.front().has_list)
    throw InputError(where + "list properties in 'vertex' are not supported");
  return header;
}

// Where each of the model's values lies in a vertex row (property indices; -1 = absent).
struct VertexLayout {
  int pos[3], dc[3], scale[3], rot[4], opacity = -1, instance = -1, class_id = -1;
  std::vector<int> rest, feat;
  int K = 1, degree = 0;  // SH coefficients per channel and their degree
};

VertexLayout vertex_layout(const Element& vertex, const std::string& where) {
  std::map<std::string, int> index;
  for (size_t i = 0; i < vertex.properties.size(); ++i) index[vertex.properties[i].name] = i;
  auto require = [&](const std::string& name) {
    auto it = index.find(name);
    if (it == index.end()) throw InputError(where + "PLY vertex lacks property '" + name + "'");
    return it->second;
  };
  VertexLayout l;
  for (int k = 0; k < 3; ++k) l.pos[k] = require(std::string(1, "xyz"[k]));
  for (int k = 0; k < 3; ++k) l.dc[k] = require("f_dc_" + std::to_string(k));
  for (int k = 0; k < 3; ++k) l.scale[k] = require("scale_" + std::to_string(k));
  for (int k = 0; k < 4; ++k) l.rot[k] = require("rot_" + std::to_string(k));
  l.opacity = require("opacity");
  l.rest = numbered(index, "f_rest_");
  l.feat = numbered(index, "feat_");
  l.K = static_cast<int>(l.rest.size()) / 3 + 1;
  l.degree = static_cast<int>(std::lround(std::sqrt(l.K))) - 1;
  if (l.rest.size() % 3 != 0 || l.degree > 3 || GaussianModel::sh_coeffs(l.degree) != l.K)
    throw InputError(where + std::to_string(l.rest.size()) +
                     " f_rest_* properties do not match an SH degree 0..3 (need 0, 9, 24 or 45)");
  l.instance = index.count("instance_id") ? index["instance_id"] : -1;
  l.class_id = index.count("class_id") ? index["class_id"] : -1;
  return l;
}

// Vertex i's values into the model.
void store_vertex(const VertexLayout& l, const std::vector<double>& values, size_t i,
                  const std::string& where, GaussianModel& model) {
  const int K = l.K;
  for (double v : values)  // stored as float: a finite double beyond its range is undefined
    if (std::isfinite(v) && std::abs(v) > std::numeric_limits<float>::max())
      throw InputError(where + "vertex " + std::to_string(i) + " holds " + std::to_string(v) +
                       ", beyond float range");
  for (int k = 0; k < 3; ++k) {
    model.means[i * 3 + k] = static_cast<float>(values[l.pos[k]]);
    model.log_scales[i * 3 + k] = static_cast<float>(values[l.scale[k]]);
    model.sh[i * K * 3 + k] = static_cast<float>(values[l.dc[k]]);
  }
  for (int c = 0; c < 3; ++c)
    for (int k = 1; k < K; ++k)
      model.sh[(i * K + k) * 3 + c] = static_cast<float>(values[l.rest[c * (K - 1) + k - 1]]);
  for (int k = 0; k < 4; ++k) model.quats[i * 4 + k] = static_cast<float>(values[l.rot[k]]);
  model.opacity_logits[i] = static_cast<float>(values[l.opacity]);
  for (size_t k = 0; k < l.feat.size(); ++k)
    model.features[i * l.feat.size() + k] = static_cast<float>(values[l.feat[k]]);
  if (l.instance >= 0) model.instance_ids[i] = id_value(values[l.instance], where, i);
  if (l.class_id >= 0) model.class_ids[i] = id_value(values[l.class_id], where, i);
}

}  // namespace

GaussianModel read_ply(const std::filesystem::path& path) {
  const std::string where = path.string() + ": ";
  require_regular_file(path, "PLY file");  // /dev/zero has no size to check counts against
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(where + "cannot open PLY file");
  const PlyHeader header = read_ply_header(in, where);
  const bool binary = header.binary;
  const Element& vertex = header.elements.front();
  const VertexLayout layout = vertex_layout(vertex, where);

  size_t row_bytes = 0;
  std::vector<size_t> offset;
  for (const auto& p : vertex.properties) {
    offset.push_back(row_bytes);
    row_bytes += scalar_size(p.type);
  }
  // The declared count against what the file can hold, before allocating for it: a 1.2 KB file
  // declaring 3e7 vertices reached 4.9 GB before failing, 2^32 ended in a bare bad_alloc. Binary
  // rows are row_bytes each; an ASCII value takes at least one character and a separator.
  const auto data_start = in.tellg();
  in.seekg(0, std::ios::end);
  const uint64_t left = static_cast<uint64_t>(in.tellg() - data_start);
  in.seekg(data_start);
  const uint64_t min_row = binary ? row_bytes : 2 * vertex.properties.size() - 1;
  if (vertex.count > left / min_row)
    throw InputError(where + "PLY data truncated: the header declares " +
                     std::to_string(vertex.count) + " vertices, but the file holds " +
                     std::to_string(left) + " bytes after its header (at least " +
                     std::to_string(min_row) + " per vertex)");

  GaussianModel model;
  model.sh_degree = layout.degree;
  model.feature_dim = static_cast<int>(layout.feat.size());
  if (layout.instance >= 0) model.instance_ids.assign(vertex.count, -1);
  if (layout.class_id >= 0) model.class_ids.assign(vertex.count, -1);
  model.resize(vertex.count);

  std::vector<double> values(vertex.properties.size());
  std::vector<char> row(row_bytes);
  for (size_t i = 0; i < vertex.count; ++i) {
    if (binary) {
      if (!in.read(row.data(), row_bytes))
        throw InputError(where + "PLY data truncated at vertex " + std::to_string(i) + " of " +
                         std::to_string(vertex.count));
      for (size_t p = 0; p < values.size(); ++p)
        values[p] = decode(vertex.properties[p].type, row.data() + offset[p]);
    } else {
      for (auto& v : values)
        if (!(in >> v))
          throw InputError(where + "PLY data truncated or not numeric at vertex " +
                           std::to_string(i));
    }
    store_vertex(layout, values, i, where, model);
  }
  return model;
}

}  // namespace gslift
