// Status propagation helpers (Abseil 20220623 ships none).
#ifndef JUGGLE_COMMON_STATUS_MACROS_H_
#define JUGGLE_COMMON_STATUS_MACROS_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"

#define JUGGLE_CONCAT_INNER_(a, b) a##b
#define JUGGLE_CONCAT_(a, b) JUGGLE_CONCAT_INNER_(a, b)

// Returns from the enclosing function if `expr` (an absl::Status) is not OK.
#define RETURN_IF_ERROR(expr)                     \
  do {                                            \
    ::absl::Status juggle_status_ = (expr);       \
    if (!juggle_status_.ok()) return juggle_status_; \
  } while (0)

// ASSIGN_OR_RETURN(lhs, expr): evaluates `expr` (an absl::StatusOr<T>); on error returns its
// status, else moves the value into `lhs` (which may be a declaration).
#define ASSIGN_OR_RETURN(lhs, expr) \
  ASSIGN_OR_RETURN_IMPL_(JUGGLE_CONCAT_(juggle_statusor_, __LINE__), lhs, expr)
#define ASSIGN_OR_RETURN_IMPL_(tmp, lhs, expr) \
  auto tmp = (expr);                           \
  if (!tmp.ok()) return tmp.status();          \
  lhs = std::move(tmp).value()

#endif  // JUGGLE_COMMON_STATUS_MACROS_H_
