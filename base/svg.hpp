// The one SVG writer behind every chart gslift draws (the report's pages, report/charts.cpp, and
// the benchmarks' charts, bench/*/): each caller lays out its own chart (bars, lines, panels) in
// user units, and this writes the elements. Numbers are written in the C locale, text is
// XML-escaped.
#pragma once

#include <array>
#include <locale>
#include <sstream>
#include <string>
#include <vector>

namespace gslift {

class Svg {
 public:
  // A width x height canvas in sans-serif of font_size; white_background paints it first.
  Svg(double width, double height, int font_size = 12, bool white_background = false) {
    s_.imbue(std::locale::classic());
    s_ << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
       << "' font-family='sans-serif' font-size='" << font_size << "'>\n";
    if (white_background) s_ << "<rect width='100%' height='100%' fill='white'/>\n";
  }

  // `attrs`: further attributes, written as given (e.g. "stroke-dasharray='6 4'").
  void line(double x1, double y1, double x2, double y2, const std::string& stroke,
            const std::string& attrs = {}) {
    s_ << "<line x1='" << x1 << "' y1='" << y1 << "' x2='" << x2 << "' y2='" << y2 << "' stroke='"
       << stroke << "'" << space(attrs) << "/>\n";
  }

  void rect(double x, double y, double width, double height, const std::string& fill,
            const std::string& attrs = {}) {
    s_ << "<rect x='" << x << "' y='" << y << "' width='" << width << "' height='" << height
       << "' fill='" << fill << "'" << space(attrs) << "/>\n";
  }

  void circle(double cx, double cy, double r, const std::string& fill,
              const std::string& attrs = {}) {
    s_ << "<circle cx='" << cx << "' cy='" << cy << "' r='" << r << "' fill='" << fill << "'"
       << space(attrs) << "/>\n";
  }

  // `d`: SVG path data, built with number() (e.g. a cubic curve "M x y C ...").
  void path(const std::string& d, const std::string& stroke, const std::string& attrs = {}) {
    s_ << "<path d='" << d << "' fill='none' stroke='" << stroke << "'" << space(attrs) << "/>\n";
  }

  // A group of the elements written until end_group(); `title` is the tooltip a browser shows
  // over them (none when empty).
  void begin_group(const std::string& title = {}, const std::string& attrs = {}) {
    s_ << "<g" << space(attrs) << ">";
    if (!title.empty()) s_ << "<title>" << escaped(title) << "</title>";
    s_ << "\n";
  }
  void end_group() { s_ << "</g>\n"; }

  void text(double x, double y, const std::string& content, const std::string& attrs = {}) {
    s_ << "<text x='" << x << "' y='" << y << "'" << space(attrs) << ">" << escaped(content)
       << "</text>\n";
  }

  void polyline(const std::vector<std::array<double, 2>>& points, const std::string& stroke,
                double stroke_width, const std::string& attrs = {}) {
    s_ << "<polyline fill='none' stroke='" << stroke << "' stroke-width='" << stroke_width << "'"
       << space(attrs) << " points='";
    for (const auto& p : points) s_ << p[0] << "," << p[1] << " ";
    s_ << "'/>\n";
  }

  // The document, closed.
  std::string str() const { return s_.str() + "</svg>\n"; }

  // A number as the writer prints it (for labels built from values).
  template <class T>
  static std::string number(T value) {
    std::ostringstream s;
    s.imbue(std::locale::classic());
    s << value;
    return s.str();
  }

 private:
  static std::string space(const std::string& attrs) { return attrs.empty() ? "" : " " + attrs; }
  static std::string escaped(const std::string& text) {
    std::string out;
    for (const char c : text) {
      if (c == '&')
        out += "&amp;";
      else if (c == '<')
        out += "&lt;";
      else if (c == '>')
        out += "&gt;";
      else
        out += c;
    }
    return out;
  }

  std::ostringstream s_;
};

}  // namespace gslift
