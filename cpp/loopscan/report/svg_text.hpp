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

// Number of Unicode code points of UTF-8 text, used to estimate label widths.
std::size_t utf8_length(std::string_view text);

}  // namespace loopscan::report
