#include "loopscan/report/html_page.hpp"

#include "loopscan/report/svg_text.hpp"

namespace loopscan::report {

namespace {
// An SVG document inlined in HTML: without its XML declaration, which HTML does not allow there.
std::string inline_svg(const std::string& svg) {
  if (svg.rfind("<?xml", 0) != 0) return svg;
  const std::size_t end = svg.find("?>");
  if (end == std::string::npos) return svg;
  std::size_t start = end + 2;
  while (start < svg.size() && (svg[start] == '\n' || svg[start] == '\r')) ++start;
  return svg.substr(start);
}
}  // namespace

std::string render_html(const HtmlPage& page) {
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
      xml_escape(page.title) +
      "</title>\n<style>body{font-family:sans-serif;max-width:1400px;margin:2em auto}"
      "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #999;padding:4px 8px;"
      "text-align:right}th{background:#eee}figure{display:inline-block;margin:0.5em;"
      "vertical-align:top}figcaption{font-size:90%;color:#333}</style>\n</head>\n<body>\n<h1>" +
      xml_escape(page.title) + "</h1>\n";
  for (const std::string& p : page.paragraphs) html += "<p>" + xml_escape(p) + "</p>\n";
  for (const Table& t : page.tables) {
    html += "<table>\n<caption>" + xml_escape(t.caption) + "</caption>\n<tr>";
    for (const std::string& h : t.header) html += "<th>" + xml_escape(h) + "</th>";
    html += "</tr>\n";
    for (const auto& row : t.rows) {
      html += "<tr>";
      for (const std::string& cell : row) html += "<td>" + xml_escape(cell) + "</td>";
      html += "</tr>\n";
    }
    html += "</table>\n";
  }
  for (const Figure& f : page.figures) {
    html += "<figure>\n" + inline_svg(f.svg) + "<figcaption>" + xml_escape(f.caption) +
            "</figcaption>\n</figure>\n";
  }
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace loopscan::report
