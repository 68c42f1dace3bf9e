#pragma once
// Text helpers for SVG output: escaping and locale-independent number formatting.
#include <cstddef>
#include <string>
#include <string_view>

namespace loopscan::report {

// Escapes & < > " ' so the text is safe both as element content and inside attributes.
std::string xml_escape(std::string_view text);

// Fixed-point with `decimals` digits, independent of the C/C++ locale (deterministic output).
std::string format_fixed(double value, int decimals);

// format_fixed, then trailing zeros (and a bare '.') removed; "-0" becomes "0".
std::string format_trimmed(double value, int decimals);

// A pixel coordinate as written in our SVG: 2 decimals, trailing zeros dropped.
std::string svg_px(double v);

// <text x y text-anchor>escaped text</text>; `extra` = further attributes (leading space).
std::string svg_text(double x, double y, const std::string& anchor, const std::string& text,
                     const std::string& extra = "");

// <line x1 y1 x2 y2 extra/> (stroke from `extra` or an enclosing group).
std::string svg_line(double x0, double y0, double x1, double y1, const std::string& extra = "");

// Number of Unicode code points of UTF-8 text, used to estimate label widths.
std::size_t utf8_length(std::string_view text);

}  // namespace loopscan::report
