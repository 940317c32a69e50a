#include "learner/http_routes.h"

#include <cstdlib>

#include "learner/dashboard_assets.h"
#include "learner/dashboard_json.h"

namespace juggle {
namespace {

constexpr char kJson[] = "application/json";

int64_t IntParam(const HttpRequest& request, const std::string& key) {
  return std::strtoll(request.Param(key, "0").c_str(), nullptr, 10);
}

}  // namespace

HttpServer::Handler LearnerHttpRoutes(const Metrics* metrics, const DashboardState* dashboard,
                                      const WorkerRegistry* registry) {
  return [=](const HttpRequest& request) {
    const std::string& path = request.path;
    if (path == "/metrics") {
      return HttpResponse{200, "text/plain; version=0.0.4", metrics->RenderPrometheus()};
    }
    if (path == "/healthz") return HttpResponse{200, "text/plain", "ok\n"};
    if (dashboard != nullptr && registry != nullptr) {
      if (path == "/" || path == "/index.html") {
        const WebAsset* page = FindDashboardAsset("index.html");
        return HttpResponse{200, page->content_type, std::string(page->body)};
      }
      if (path.rfind("/static/", 0) == 0) {
        if (const WebAsset* asset = FindDashboardAsset(path.substr(8))) {
          // The page's own files change with the binary; the libraries with Debian's package.
          return HttpResponse{200, asset->content_type, std::string(asset->body),
                              "public, max-age=3600"};
        }
      }
      if (path == "/api/status") {
        return HttpResponse{200, kJson, StatusJson(LiveStatus(*dashboard, *registry, *metrics))};
      }
      if (path == "/api/history") {
        return HttpResponse{200, kJson,
                            HistoryJson(dashboard->HistorySince(IntParam(request, "since"),
                                                                IntParam(request, "stride")))};
      }
      if (path == "/api/evals") {
        return HttpResponse{200, kJson, EvaluationsJson(dashboard->Evaluations())};
      }
    }
    return HttpResponse{404, "text/plain",
                        "not found; try / (dashboard), /api/status, /api/history, /api/evals, "
                        "/metrics or /healthz\n"};
  };
}

}  // namespace juggle
