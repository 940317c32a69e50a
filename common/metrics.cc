#include "common/metrics.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle {

std::string Metrics::LabelKey(const std::map<std::string, std::string>& labels) {
  if (labels.empty()) return "";
  std::string key = "{";
  bool first = true;
  for (const auto& [k, v] : labels) {
    absl::StrAppend(&key, first ? "" : ",", k, "=\"", v, "\"");
    first = false;
  }
  return key + "}";
}

void Metrics::Declare(const std::string& name, const std::string& type, const std::string& help,
                      std::vector<double> buckets) {
  std::lock_guard<std::mutex> lock(mu_);
  Family& f = families_[name];
  f.type = type;
  f.help = help;
  f.buckets = std::move(buckets);
  f.bucket_counts.assign(f.buckets.size(), 0);
}

void Metrics::Add(const std::string& name, double delta,
                  const std::map<std::string, std::string>& labels) {
  std::lock_guard<std::mutex> lock(mu_);
  families_[name].series[LabelKey(labels)] += delta;
}

void Metrics::Set(const std::string& name, double value,
                  const std::map<std::string, std::string>& labels) {
  std::lock_guard<std::mutex> lock(mu_);
  families_[name].series[LabelKey(labels)] = value;
}

void Metrics::Observe(const std::string& name, double value) {
  std::lock_guard<std::mutex> lock(mu_);
  Family& f = families_[name];
  for (size_t i = 0; i < f.buckets.size(); ++i) {
    if (value <= f.buckets[i]) f.bucket_counts[i] += 1;
  }
  f.sum += value;
  f.count += 1;
}

double Metrics::Get(const std::string& name,
                    const std::map<std::string, std::string>& labels) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto f = families_.find(name);
  if (f == families_.end()) return 0;
  if (f->second.type == "histogram") return f->second.count;
  auto s = f->second.series.find(LabelKey(labels));
  return s == f->second.series.end() ? 0 : s->second;
}

void Metrics::Erase(const std::string& name, const std::string& label, const std::string& value) {
  std::lock_guard<std::mutex> lock(mu_);
  auto f = families_.find(name);
  if (f == families_.end()) return;
  const std::string needle = absl::StrCat(label, "=\"", value, "\"");
  for (auto it = f->second.series.begin(); it != f->second.series.end();) {
    it = it->first.find(needle) != std::string::npos ? f->second.series.erase(it) : std::next(it);
  }
}

std::string Metrics::RenderPrometheus() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::string out;
  for (const auto& [name, f] : families_) {
    absl::StrAppend(&out, "# HELP ", name, " ", f.help, "\n# TYPE ", name, " ", f.type, "\n");
    if (f.type == "histogram") {
      for (size_t i = 0; i < f.buckets.size(); ++i) {
        absl::StrAppend(&out, name, "_bucket{le=\"", absl::StrFormat("%g", f.buckets[i]), "\"} ",
                        absl::StrFormat("%.17g", f.bucket_counts[i]), "\n");
      }
      absl::StrAppend(&out, name, "_bucket{le=\"+Inf\"} ", absl::StrFormat("%.17g", f.count), "\n",
                      name, "_sum ", absl::StrFormat("%.17g", f.sum), "\n", name, "_count ",
                      absl::StrFormat("%.17g", f.count), "\n");
      continue;
    }
    for (const auto& [labels, value] : f.series) {
      absl::StrAppend(&out, name, labels, " ", absl::StrFormat("%.17g", value), "\n");
    }
  }
  return out;
}

}  // namespace juggle
