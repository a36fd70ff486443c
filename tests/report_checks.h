#pragma once
// Readers of the report's HTML for the report tests: links, the totals row,
// the overview map's parcels and legend, the histogram's bins; and the 3D
// view as headless Chromium shows it (tests/js/report_view.js).
#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace c3d::test {

inline const std::string kJsChecks = std::string(C3D_SOURCE_DIR) + "/tests/js";

// node, puppeteer-core (tests/js/node_modules) and Chromium, for report_view.js.
inline bool view_tools() {
  return std::filesystem::exists(kJsChecks + "/node_modules/puppeteer-core/package.json") && !chromium().empty() &&
         !shell("command -v node").empty();
}

// tests/js/report_view.js's account of `page` in headless Chromium (its usage
// gives the options); {} when it failed, which fails the test.
inline nlohmann::json viewed(const std::string& page, const std::string& png, const std::string& options) {
  int rc = -1;
  const std::string out = shell("CHROMIUM=" + chromium() + " timeout 300 node " + kJsChecks + "/report_view.js " +
                                page + " " + png + " " + options + " 2>&1", &rc);
  EXPECT_EQ(rc, 0) << out;
  return rc == 0 ? nlohmann::json::parse(out) : nlohmann::json::object();
}

inline std::vector<std::string> hrefs(const std::string& html) {
  std::vector<std::string> out;
  static const std::regex re("href=\"([^\"]*)\"");
  for (std::sregex_iterator it(html.begin(), html.end(), re), end; it != end; ++it) out.push_back((*it)[1]);
  return out;
}

// "dir/of/from" + "../x.html#p3" -> "dir/x.html#p3" (lexically, as a browser does).
inline std::string resolve(const std::string& from, const std::string& href) {
  const size_t hash = href.find('#');
  const std::string file = href.substr(0, hash), frag = hash == std::string::npos ? "" : href.substr(hash);
  if (file.empty()) return from + frag;
  return (std::filesystem::path(from).parent_path() / file).lexically_normal().generic_string() + frag;
}

// First number in an HTML cell: "1,234.50&nbsp;&plusmn;..." -> 1234.5.
inline double cell_number(const std::string& text) {
  std::string digits;
  for (char c : text) {
    if ((c >= '0' && c <= '9') || c == '.' || (c == '-' && digits.empty())) digits += c;
    else if (c == ',' && !digits.empty()) continue;
    else if (!digits.empty()) break;
  }
  return digits.empty() ? std::nan("") : std::stod(digits);
}

// The cells of the row <tr class="cls"> by their data-key, read as printed.
inline std::map<std::string, std::string> row_cells(const std::string& html, const std::string& cls) {
  std::map<std::string, std::string> out;
  const size_t from = html.find("<tr class=\"" + cls + "\">");
  if (from == std::string::npos) return out;
  const std::string row = html.substr(from, html.find("</tr>", from) - from);
  static const std::regex re("data-key=\"([^\"]+)\">(.*?)</td>");
  for (std::sregex_iterator it(row.begin(), row.end(), re), end; it != end; ++it) out[(*it)[1]] = (*it)[2];
  return out;
}

// An attribute of an element's opening tag text.
inline std::string attr(const std::string& tag, const std::string& name) {
  const size_t at = tag.find(" " + name + "=\"");
  if (at == std::string::npos) return "";
  const size_t from = at + name.size() + 3;
  return tag.substr(from, tag.find('"', from) - from);
}

// Opening tags "<path ..." (or another element) that carry the attribute `marker`.
inline std::vector<std::string> tags_with(const std::string& html, const std::string& element,
                                          const std::string& marker) {
  std::vector<std::string> out;
  for (size_t at = html.find("<" + element + " "); at != std::string::npos;
       at = html.find("<" + element + " ", at + 1)) {
    std::string tag = html.substr(at, html.find('>', at) - at);
    if (tag.find(" " + marker + "=\"") != std::string::npos) out.push_back(tag);
  }
  return out;
}

}  // namespace c3d::test
