// A small metrics registry rendered in Prometheus text format: counters and gauges with
// optional label sets, and fixed-bucket histograms. Thread-safe (one mutex; metrics are
// updated a few times per chunk, not per env step).
#ifndef JUGGLE_COMMON_METRICS_H_
#define JUGGLE_COMMON_METRICS_H_

#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace juggle {

// Seconds since the Unix epoch (the wall clock of timestamps in metrics and records).
double UnixNow();

class Metrics {
 public:
  // Declares a metric (type "counter", "gauge" or "histogram") with its help text.
  void Declare(const std::string& name, const std::string& type, const std::string& help,
               std::vector<double> buckets = {});
  // labels: e.g. {{"reason", "nan"}}.
  void Add(const std::string& name, double delta, const std::map<std::string, std::string>& labels = {});
  void Set(const std::string& name, double value, const std::map<std::string, std::string>& labels = {});
  void Observe(const std::string& name, double value);
  double Get(const std::string& name, const std::map<std::string, std::string>& labels = {}) const;
  // Removes every series of `name` whose labels include `label`=`value`.
  void Erase(const std::string& name, const std::string& label, const std::string& value);
  // Every series of `name` (counter or gauge) with its labels; empty if none.
  std::vector<std::pair<std::map<std::string, std::string>, double>> Series(
      const std::string& name) const;
  struct HistogramValues {
    std::vector<double> upper_bounds;       // the declared buckets (+Inf implied)
    std::vector<double> cumulative_counts;  // observations <= each bound
    double sum = 0, count = 0;
  };
  HistogramValues Histogram(const std::string& name) const;
  // Prometheus text format 0.0.4; label values escaped (backslash, quote, newline).
  std::string RenderPrometheus() const;

 private:
  struct Family {
    std::string type, help;
    std::vector<double> buckets;
    std::map<std::string, double> series;  // rendered label set -> value
    std::map<std::string, std::map<std::string, std::string>> labels;  // rendered -> labels
    std::vector<double> bucket_counts;
    double sum = 0;
    double count = 0;
  };
  static std::string LabelKey(const std::map<std::string, std::string>& labels);
  mutable std::mutex mu_;
  std::map<std::string, Family> families_;
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_METRICS_H_
