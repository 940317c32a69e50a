#!/usr/bin/env bash
# deploy/prometheus is valid and its alerts behave: `promtool check config` and `check rules`,
# then the unit tests of every alert and recording rule (`promtool test rules`). Also every
# query of deploy/grafana/juggle.json parses as PromQL (checked as recording rules, with the
# dashboard's variables filled in). Skips (exit 77) only when promtool (Debian's prometheus
# package) is not installed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if ! command -v promtool >/dev/null; then
  echo "SKIP: promtool not installed (apt-get install prometheus; scripts/dev/install_deps.sh)"
  exit 77
fi
cd "$root/deploy/prometheus"
promtool check config prometheus.yml
promtool check rules recording_rules.yml alerting_rules.yml
promtool test rules alerting_rules_test.yml

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 - "$root/deploy/grafana/juggle.json" > "$tmp/grafana_queries.yml" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
exprs = [t["expr"] for p in d["panels"] for t in p.get("targets", [])]
exprs += [v["query"]["query"] for v in d["templating"]["list"]]
print("groups:\n  - name: grafana_queries\n    rules:")
for i, e in enumerate(exprs):
    e = e.replace("$__rate_interval", "5m").replace("$job", ".*").replace("$instance", ".*")
    if e.startswith("label_values("):  # Grafana's own function: check its selector
        e = e[len("label_values("):].rsplit(",", 1)[0]
    print(f"      - record: grafana:query_{i}\n        expr: {json.dumps(e)}")
print(f"{len(exprs)} queries", file=sys.stderr)
PY
promtool check rules "$tmp/grafana_queries.yml"
