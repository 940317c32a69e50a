#include "common/outcome.h"

#include "absl/strings/str_cat.h"

namespace juggle {

std::vector<std::string> CommonOutcomeNames() { return {"running", "time_limit", "diverged"}; }

std::string OutcomeName(const std::vector<std::string>& names, Outcome o) {
  const size_t i = static_cast<size_t>(o);
  return i < names.size() ? names[i] : absl::StrCat("outcome_", i);
}

}  // namespace juggle
