#include "report/html.hpp"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "base/errors.hpp"

namespace gslift::report {

namespace fs = std::filesystem;

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* const kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 |
                       uint8_t(bytes[i + 2]);
    for (int s : {18, 12, 6, 0}) out += kAlphabet[(v >> s) & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    out += kAlphabet[(v >> 18) & 63], out += kAlphabet[(v >> 12) & 63], out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8;
    out += kAlphabet[(v >> 18) & 63], out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63], out += '=';
  }
  return out;
}

std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("cannot read " + file.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

namespace {
uint32_t big_endian(const std::string& b, size_t at, int bytes) {
  uint32_t v = 0;
  for (int k = 0; k < bytes; ++k) v = v << 8 | uint8_t(b[at + size_t(k)]);
  return v;
}
}  // namespace

PixelSize picture_size(const std::string& b) {
  // PNG: 8-byte signature, then the IHDR chunk (length, "IHDR", width, height).
  if (b.size() >= 24 && b.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0 && b.compare(12, 4, "IHDR") == 0)
    return {big_endian(b, 16, 4), big_endian(b, 20, 4)};
  // JPEG: walk the marker segments up to a start-of-frame (SOF0..SOF15 but DHT, JPG, DAC).
  if (b.size() >= 4 && uint8_t(b[0]) == 0xFF && uint8_t(b[1]) == 0xD8) {
    size_t at = 2;
    while (at + 9 < b.size()) {
      if (uint8_t(b[at]) != 0xFF) return {};
      const uint8_t marker = uint8_t(b[at + 1]);
      if (marker == 0xFF) {  // fill byte
        ++at;
        continue;
      }
      const uint32_t length = big_endian(b, at + 2, 2);
      if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC)
        return {big_endian(b, at + 7, 2), big_endian(b, at + 5, 2)};
      at += 2 + length;
    }
  }
  return {};
}

std::string picture_mime(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = char(std::tolower(uint8_t(c)));
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  return {};
}

namespace {

std::vector<std::string> table_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (size_t k = 1; k < line.size(); ++k) {
    if (line[k] != '|') {
      cell += line[k];
      continue;
    }
    const size_t first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
    cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
    cell.clear();
  }
  return cells;
}

}  // namespace

std::string markdown_table_html(const std::string& markdown) {
  std::vector<std::vector<std::string>> rows;
  std::vector<bool> right;
  size_t start = 0;
  while (start < markdown.size()) {
    size_t end = markdown.find('\n', start);
    if (end == std::string::npos) end = markdown.size();
    std::string line = markdown.substr(start, end - start);
    start = end + 1;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.size() < 2 || line.front() != '|' || line.back() != '|') continue;
    std::vector<std::string> cells = table_cells(line);
    if (!rows.empty() && right.empty() && !cells.empty() &&
        cells[0].find("---") != std::string::npos) {
      for (const auto& c : cells) right.push_back(!c.empty() && c.back() == ':');
      continue;
    }
    rows.push_back(std::move(cells));
  }
  if (rows.empty()) return {};
  std::string h = "<table class=\"markdown\">\n";
  for (size_t r = 0; r < rows.size(); ++r) {
    h += "<tr>";
    for (size_t c = 0; c < rows[r].size(); ++c) {
      const char* tag = r == 0 ? "th" : "td";
      h += std::string("<") + tag + (c < right.size() && right[c] ? " class=\"num\"" : "") + ">" +
           html_escape(rows[r][c]) + "</" + tag + ">";
    }
    h += "</tr>\n";
  }
  return h + "</table>\n";
}

std::string size_text(uintmax_t bytes) {
  char buf[32];
  if (bytes < 1024)
    std::snprintf(buf, sizeof buf, "%ju B", bytes);
  else if (bytes < 1024 * 1024)
    std::snprintf(buf, sizeof buf, "%.1f KB", double(bytes) / 1024);
  else
    std::snprintf(buf, sizeof buf, "%.1f MB", double(bytes) / (1024 * 1024));
  return buf;
}

namespace {
constexpr const char* kStyle = R"css(
:root { --ink: #1f2933; --muted: #5f6b76; --line: #dde3e8; --ok: #3d8b4f; --bad: #c0392b; }
* { box-sizing: border-box; }
body { margin: 0; font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif;
       color: var(--ink); background: #f4f6f8; }
main { max-width: 1280px; margin: 0 auto; padding: 20px 28px 60px; }
h1 { font-size: 24px; margin: 8px 0 4px; }
h2 { font-size: 18px; margin: 0 0 12px; }
h3 { font-size: 15px; margin: 14px 0 6px; }
section { background: white; border: 1px solid var(--line); border-radius: 8px;
          padding: 16px 20px; margin: 16px 0; }
.meta { color: var(--muted); margin: 0; }
.meta span { margin-right: 18px; white-space: nowrap; }
.badge { display: inline-block; padding: 1px 9px; border-radius: 10px; font-size: 12px;
         font-weight: 600; color: white; background: #8a8a8a; vertical-align: middle; }
.badge.ok { background: var(--ok); } .badge.failed, .badge.interrupted { background: var(--bad); }
.badge.hit, .badge.cached { background: #2f6db5; } .badge.miss { background: #b7791f; }
.badge.holds { background: var(--ok); } .badge.below { background: var(--bad); }
figure.side-by-side { margin: 0 0 14px; } figure.side-by-side img { max-width: 100%; height: auto; }
.error { background: #fbe4e1; border: 1px solid #e6a59c; color: #7b1d12; border-radius: 6px;
         padding: 10px 14px; white-space: pre-wrap; font-family: ui-monospace, monospace; }
.note { color: var(--muted); font-size: 13px; }
table { border-collapse: collapse; font-size: 13px; }
th, td { padding: 4px 10px; border-bottom: 1px solid var(--line); text-align: left;
         vertical-align: top; }
th { background: #f7f9fb; font-weight: 600; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
tr.failed td { background: #fdf1ef; }
.scroll { overflow-x: auto; }
.bar { display: inline-block; height: 8px; background: #9db8d9; border-radius: 2px; }
.chart { margin: 0; overflow-x: auto; }
.chart figcaption, figure.picture figcaption { color: var(--muted); font-size: 12px; margin-top: 4px; }
.charts { display: grid; grid-template-columns: repeat(auto-fill, minmax(540px, 1fr)); gap: 16px; }
.cards { display: grid; grid-template-columns: repeat(auto-fill, minmax(300px, 1fr)); gap: 14px;
         align-items: start; }
.cards > div { border: 1px solid var(--line); border-radius: 6px; padding: 8px 10px; }
.pictures { display: grid; grid-template-columns: repeat(auto-fill, minmax(300px, 1fr));
            gap: 14px; }
figure.picture { margin: 0; }
figure.picture img { width: 100%; height: auto; border: 1px solid var(--line);
                     border-radius: 4px; background: #eee; image-rendering: auto; }
details { margin: 6px 0; } summary { cursor: pointer; font-weight: 600; }
code { font-family: ui-monospace, monospace; font-size: 12.5px; }
a { color: #2f6db5; }
)css";
}  // namespace

// No frame-ancestors: a policy delivered in a <meta> element cannot carry it (the browser ignores
// it and says so on the console; report_browser_test allows no console message).
const char* const kContentSecurityPolicy =
    "default-src 'none'; img-src 'self' data: file:; style-src 'unsafe-inline'; "
    "base-uri 'none'; form-action 'none'";

std::string relative_href(const fs::path& relative) {
  static const char* hex = "0123456789ABCDEF";
  std::string out = "./";
  for (unsigned char c : relative.generic_string()) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

std::string html_page(const std::string& title, const std::string& body) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta http-equiv=\"Content-Security-Policy\" content=\"" +
         std::string(kContentSecurityPolicy) +
         "\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
         "<title>" +
         html_escape(title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<main>\n" +
         body + "</main>\n</body>\n</html>\n";
}

}  // namespace gslift::report
