// The learner's HTTP endpoints: /metrics (Prometheus text format), /healthz, and the dashboard:
// the page (/), its files (/static/...) and its JSON API (/api/status, /api/history,
// /api/evals; docs/dashboard.md). Thread-safe: handlers only read thread-safe state.
#ifndef JUGGLE_LEARNER_HTTP_ROUTES_H_
#define JUGGLE_LEARNER_HTTP_ROUTES_H_

#include "common/http_server.h"
#include "common/metrics.h"
#include "learner/dashboard_state.h"
#include "learner/worker_registry.h"

namespace juggle {

// REQUIRES: everything outlives the handler. `dashboard` and `registry` may be null: then only
// /metrics and /healthz are served.
HttpServer::Handler LearnerHttpRoutes(const Metrics* metrics, const DashboardState* dashboard,
                                      const WorkerRegistry* registry);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_HTTP_ROUTES_H_
