#include "common/metrics.h"

#include <chrono>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle {

double UnixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}
namespace {

// A sample value as the exposition format spells it: NaN, +Inf, -Inf, else 17 digits.
std::string FormatValue(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  return absl::StrFormat("%.17g", v);
}

}  // namespace

std::string Metrics::LabelKey(const std::map<std::string, std::string>& labels) {
  if (labels.empty()) return "";
  std::string key = "{";
  bool first = true;
  for (const auto& [k, v] : labels) {
    std::string escaped;
    for (char c : v) {
      if (c == '\\') escaped += "\\\\";
      else if (c == '"') escaped += "\\\"";
      else if (c == '\n') escaped += "\\n";
      else escaped += c;
    }
    absl::StrAppend(&key, first ? "" : ",", k, "=\"", escaped, "\"");
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
  const std::string key = LabelKey(labels);
  std::lock_guard<std::mutex> lock(mu_);
  Family& f = families_[name];
  f.series[key] += delta;
  if (!labels.empty()) f.labels.emplace(key, labels);
}

void Metrics::Set(const std::string& name, double value,
                  const std::map<std::string, std::string>& labels) {
  const std::string key = LabelKey(labels);
  std::lock_guard<std::mutex> lock(mu_);
  Family& f = families_[name];
  f.series[key] = value;
  if (!labels.empty()) f.labels.emplace(key, labels);
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
    if (it->first.find(needle) != std::string::npos) {
      f->second.labels.erase(it->first);
      it = f->second.series.erase(it);
    } else {
      ++it;
    }
  }
}

std::vector<std::pair<std::map<std::string, std::string>, double>> Metrics::Series(
    const std::string& name) const {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<std::pair<std::map<std::string, std::string>, double>> out;
  auto f = families_.find(name);
  if (f == families_.end()) return out;
  for (const auto& [key, value] : f->second.series) {
    auto l = f->second.labels.find(key);
    out.emplace_back(l == f->second.labels.end() ? std::map<std::string, std::string>{}
                                                 : l->second,
                     value);
  }
  return out;
}

Metrics::HistogramValues Metrics::Histogram(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mu_);
  HistogramValues h;
  auto f = families_.find(name);
  if (f == families_.end()) return h;
  h.upper_bounds = f->second.buckets;
  h.cumulative_counts = f->second.bucket_counts;
  h.sum = f->second.sum;
  h.count = f->second.count;
  return h;
}

std::string Metrics::RenderPrometheus() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::string out;
  for (const auto& [name, f] : families_) {
    absl::StrAppend(&out, "# HELP ", name, " ", f.help, "\n# TYPE ", name, " ", f.type, "\n");
    if (f.type == "histogram") {
      for (size_t i = 0; i < f.buckets.size(); ++i) {
        absl::StrAppend(&out, name, "_bucket{le=\"", absl::StrFormat("%g", f.buckets[i]), "\"} ",
                        FormatValue(f.bucket_counts[i]), "\n");
      }
      absl::StrAppend(&out, name, "_bucket{le=\"+Inf\"} ", FormatValue(f.count), "\n",
                      name, "_sum ", FormatValue(f.sum), "\n", name, "_count ",
                      FormatValue(f.count), "\n");
      continue;
    }
    for (const auto& [labels, value] : f.series) {
      absl::StrAppend(&out, name, labels, " ", FormatValue(value), "\n");
    }
  }
  return out;
}

}  // namespace juggle
