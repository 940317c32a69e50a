// The dashboard's web files, embedded in the binary at build time (cmake/embed_files.cmake):
// web/dashboard.{html,js,css} and the chart libraries from Debian's libjs-chart.js and
// libjs-d3 packages. The learner serves them; `juggle dashboard` inlines them into one HTML
// file. Immutable; thread-safe.
#ifndef JUGGLE_LEARNER_DASHBOARD_ASSETS_H_
#define JUGGLE_LEARNER_DASHBOARD_ASSETS_H_

#include <string>
#include <string_view>
#include <vector>

namespace juggle {

struct WebAsset {
  const char* name;          // "index.html", "dashboard.js", "chart.min.js", ...
  const char* content_type;
  std::string_view body;
};

const std::vector<WebAsset>& DashboardAssets();
// The asset called `name`, or null.
const WebAsset* FindDashboardAsset(std::string_view name);

// One self-contained HTML page: index.html with every script and style sheet inlined and
// `data_script` (JavaScript that sets window.JUGGLE_DATA) run before the dashboard's script.
std::string InlineDashboardPage(const std::string& data_script);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DASHBOARD_ASSETS_H_
