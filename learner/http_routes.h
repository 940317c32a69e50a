// The learner's HTTP endpoints: /metrics (Prometheus text format) and /healthz. The dashboard's
// pages and JSON API join them here. Thread-safe: the handler only reads thread-safe state.
#ifndef JUGGLE_LEARNER_HTTP_ROUTES_H_
#define JUGGLE_LEARNER_HTTP_ROUTES_H_

#include "common/http_server.h"
#include "common/metrics.h"

namespace juggle {

// REQUIRES: `metrics` outlives the handler.
HttpServer::Handler LearnerHttpRoutes(const Metrics* metrics);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_HTTP_ROUTES_H_
