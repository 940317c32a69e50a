// Range checks of parsed config messages, driven by the schema: every float and double field
// set in a message (at any depth, every element of repeated ones) must be finite and within
// its declared (range) option (proto/field_range.proto), or within ±kUndeclaredFloatBound when
// it declares none; integer fields with a declared range must lie in it. ParseTextMessage
// applies this to every config, graph and start-state file.
#ifndef JUGGLE_COMMON_CONFIG_RANGES_H_
#define JUGGLE_COMMON_CONFIG_RANGES_H_

#include "absl/status/status.h"
#include "common/source_locator.h"
#include "google/protobuf/message.h"

namespace juggle {

inline constexpr double kUndeclaredFloatBound = 1e6;

// OK, or INVALID_ARGUMENT for the first offending value: "file:line:col: path: <why>", with the
// memory a count would need when its range declares bytes_each.
absl::Status CheckFieldRanges(const google::protobuf::Message& message, const SourceLocator& where);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CONFIG_RANGES_H_
