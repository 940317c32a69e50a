#include "learner/dashboard_assets.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "learner/dashboard_asset_files.h"

namespace juggle {
namespace {

absl::string_view View(std::string_view s) { return absl::string_view(s.data(), s.size()); }

}  // namespace

const std::vector<WebAsset>& DashboardAssets() {
  static const std::vector<WebAsset> assets = {
      {"index.html", "text/html; charset=utf-8", kDashboardHtml},
      {"dashboard.js", "application/javascript; charset=utf-8", kDashboardJs},
      {"dashboard.css", "text/css; charset=utf-8", kDashboardCss},
      {"chart.min.js", "application/javascript; charset=utf-8", kChartJs},
      {"d3.min.js", "application/javascript; charset=utf-8", kD3Js},
  };
  return assets;
}

const WebAsset* FindDashboardAsset(std::string_view name) {
  for (const WebAsset& asset : DashboardAssets()) {
    if (name == asset.name) return &asset;
  }
  return nullptr;
}

std::string InlineDashboardPage(const std::string& data_script) {
  const WebAsset* page = FindDashboardAsset("index.html");
  if (page == nullptr) return "";
  std::vector<std::pair<std::string, std::string>> replacements;
  for (const WebAsset& asset : DashboardAssets()) {
    const std::string name = asset.name;
    // A script's text may not contain "</script" (nor a style's "</style"): escape it.
    if (name.size() > 3 && name.compare(name.size() - 3, 3, ".js") == 0) {
      replacements.emplace_back(
          absl::StrCat("<script src=\"static/", name, "\"></script>"),
          absl::StrCat("<script>", absl::StrReplaceAll(View(asset.body), {{"</script", "<\\/script"}}),
                       "</script>"));
    } else if (name.size() > 4 && name.compare(name.size() - 4, 4, ".css") == 0) {
      replacements.emplace_back(
          absl::StrCat("<link rel=\"stylesheet\" href=\"static/", name, "\">"),
          absl::StrCat("<style>", absl::StrReplaceAll(View(asset.body), {{"</style", "<\\/style"}}),
                       "</style>"));
    }
  }
  replacements.emplace_back(
      "<!-- juggle:data -->",
      absl::StrCat("<script>", absl::StrReplaceAll(data_script, {{"</", "<\\/"}}), "</script>"));
  return absl::StrReplaceAll(View(page->body), replacements);
}

}  // namespace juggle
