// Minimal command-line flags for the `juggle` subcommands: --name=value or --name value, and
// bare --name for booleans. Unknown flags are errors, so typos never pass silently.
#ifndef JUGGLE_APP_FLAGS_H_
#define JUGGLE_APP_FLAGS_H_

#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace juggle {

struct FlagSpec {
  std::string name;
  std::string default_value;
  std::string help;
};

class Flags {
 public:
  // Parses argv[first..argc). INVALID_ARGUMENT for an unknown flag or a missing value.
  static absl::StatusOr<Flags> Parse(int argc, char** argv, int first,
                                     const std::vector<FlagSpec>& specs);
  std::string Get(const std::string& name) const;
  absl::StatusOr<int64_t> GetInt(const std::string& name) const;
  absl::StatusOr<double> GetDouble(const std::string& name) const;
  bool GetBool(const std::string& name) const;
  bool help() const { return help_; }
  const std::vector<std::string>& positional() const { return positional_; }
  // "  --name=default  help" lines.
  static std::string Usage(const std::vector<FlagSpec>& specs);

 private:
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
  bool help_ = false;
};

}  // namespace juggle

#endif  // JUGGLE_APP_FLAGS_H_
