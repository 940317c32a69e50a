// The dashboard's files as compiled in at build time (cmake/embed_files.cmake generates
// dashboard_asset_files.cc in the build folder). dashboard_assets.h serves them by name.
#ifndef JUGGLE_LEARNER_DASHBOARD_ASSET_FILES_H_
#define JUGGLE_LEARNER_DASHBOARD_ASSET_FILES_H_

namespace juggle {

extern const char kDashboardHtml[];  // web/dashboard.html
extern const char kDashboardJs[];    // web/dashboard.js
extern const char kDashboardCss[];   // web/dashboard.css
extern const char kChartJs[];        // Debian libjs-chart.js: chart.min.js
extern const char kD3Js[];           // Debian libjs-d3: d3.min.js

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DASHBOARD_ASSET_FILES_H_
