// Composing run configs (RunConfig.base_config): a derived config is its base with the
// derived file's fields laid over it. Pure functions on protobuf messages (reflection).
#ifndef JUGGLE_COMMON_CONFIG_MERGE_H_
#define JUGGLE_COMMON_CONFIG_MERGE_H_

#include <string>

#include "google/protobuf/message.h"

namespace juggle {

// Lays `derived` over `base`: every field set in `derived` replaces the base's value — a
// repeated field as a whole (not appended, unlike Message::MergeFrom), a singular message
// field field by field, recursively; setting another case of a oneof clears the base's case.
// REQUIRES: both of the same type.
void MergeOver(const google::protobuf::Message& derived, google::protobuf::Message* base);

// Rewrites the relative file names of `message` — string fields named `*_file`, set or
// defaulted (non-empty) — from names relative to `from_dir` into names relative to `to_dir`, so
// that they name the same files from there. Sub-messages whose defaults name files are made
// present for it (not other cases of a oneof). No change when the folders are the same.
void RebaseFileNames(const std::string& from_dir, const std::string& to_dir,
                     google::protobuf::Message* message);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CONFIG_MERGE_H_
