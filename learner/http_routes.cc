#include "learner/http_routes.h"

namespace juggle {

HttpServer::Handler LearnerHttpRoutes(const Metrics* metrics) {
  return [metrics](const std::string& path) {
    if (path == "/metrics") {
      return HttpResponse{200, "text/plain; version=0.0.4", metrics->RenderPrometheus()};
    }
    if (path == "/healthz") return HttpResponse{200, "text/plain", "ok\n"};
    return HttpResponse{404, "text/plain", "try /metrics or /healthz\n"};
  };
}

}  // namespace juggle
