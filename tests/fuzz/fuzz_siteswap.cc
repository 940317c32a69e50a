// libFuzzer: any text as a siteswap (`juggle siteswap`, toss patterns). Invariant: a valid
// siteswap's average is its ball count, and formatting it parses back to the same throws.
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <string_view>

#include "envs/toss/siteswap.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<juggle::toss::Siteswap> parsed = juggle::toss::Siteswap::Parse(text);
  if (!parsed.ok()) return 0;
  const std::vector<int>& throws = parsed->throws();
  const int sum = std::accumulate(throws.begin(), throws.end(), 0);
  if (throws.empty() || sum % static_cast<int>(throws.size()) != 0) std::abort();
  absl::StatusOr<juggle::toss::Siteswap> again = juggle::toss::Siteswap::Parse(juggle::toss::FormatSiteswap(throws));
  if (!again.ok() || again->throws() != throws) std::abort();
  return 0;
}
