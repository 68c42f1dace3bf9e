#include "loopscan/report/svg_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace loopscan::report {

std::string xml_escape(std::string_view text) {
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
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string format_fixed(double value, int decimals) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "INF" : "-INF";
  decimals = std::clamp(decimals, 0, 17);
  char buffer[400];  // enough for any double in fixed notation with <= 17 decimals
  const auto res =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, decimals);
  return std::string(buffer, res.ptr);
}

std::string format_trimmed(double value, int decimals) {
  std::string s = format_fixed(value, decimals);
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

std::size_t utf8_length(std::string_view text) {
  // Continuation bytes look like 10xxxxxx.
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) {
    return (static_cast<unsigned char>(c) & 0xC0u) != 0x80u;
  }));
}

std::string svg_px(double v) { return format_trimmed(v, 2); }

std::string svg_text(double x, double y, const std::string& anchor, const std::string& text,
                     const std::string& extra) {
  return "<text x=\"" + svg_px(x) + "\" y=\"" + svg_px(y) + "\" text-anchor=\"" + anchor + "\"" +
         extra + ">" + xml_escape(text) + "</text>\n";
}

std::string svg_line(double x0, double y0, double x1, double y1, const std::string& extra) {
  return "<line x1=\"" + svg_px(x0) + "\" y1=\"" + svg_px(y0) + "\" x2=\"" + svg_px(x1) +
         "\" y2=\"" + svg_px(y1) + "\"" + extra + "/>\n";
}

}  // namespace loopscan::report
