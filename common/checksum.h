// The project's file checksum: 64-bit FNV-1a over a payload, as checkpoints (learner/checkpoint.h)
// and exported-policy files (common/policy_file.h) store it after their magic. Detects truncation
// and flipped bytes; not a defence against a crafted file.
#ifndef JUGGLE_COMMON_CHECKSUM_H_
#define JUGGLE_COMMON_CHECKSUM_H_

#include <cstdint>
#include <string_view>

namespace juggle {

// 64-bit FNV-1a of `bytes`.
uint64_t Fnv1a64(std::string_view bytes);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CHECKSUM_H_
