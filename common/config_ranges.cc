#include "common/config_ranges.h"

#include <cmath>
#include <cstdint>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "proto/field_range.pb.h"

namespace juggle {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

std::string Number(double v) { return absl::StrFormat("%.15g", v); }

std::string Memory(double bytes) {
  if (bytes >= double(1 << 30)) return absl::StrFormat("%.0f GiB", bytes / double(1 << 30));
  return absl::StrFormat("%.0f MiB", bytes / double(1 << 20));
}

// Why `value` is out of range for `field`, or "" when it is fine.
std::string Problem(const FieldDescriptor& field, double value, bool is_float) {
  if (is_float && !std::isfinite(value)) return absl::StrCat(Number(value), " is not a finite number");
  if (!field.options().HasExtension(config::range)) {
    if (is_float && std::abs(value) > kUndeclaredFloatBound) {
      return absl::StrCat(Number(value), " is beyond ±", Number(kUndeclaredFloatBound),
                          ", the bound of fields without a declared range");
    }
    return "";
  }
  const config::FieldRange& range = field.options().GetExtension(config::range);
  const double lo = range.has_min() ? range.min() : -HUGE_VAL;
  const double hi = range.has_max() ? range.max() : HUGE_VAL;
  if (value >= lo && value <= hi) return "";
  std::string why = absl::StrCat(Number(value), " is outside [", Number(lo), ", ", Number(hi), "]");
  if (range.has_unit()) absl::StrAppend(&why, " ", range.unit());
  if (range.has_bytes_each() && value > hi) {
    absl::StrAppend(&why, " (", Number(value), " would need about ",
                    Memory(value * range.bytes_each()), " of memory)");
  }
  return why;
}

absl::Status Walk(const Message& message, const SourceLocator& where, FieldPath* path) {
  const Reflection* r = message.GetReflection();
  std::vector<const FieldDescriptor*> fields;
  r->ListFields(message, &fields);
  for (const FieldDescriptor* f : fields) {
    const int n = f->is_repeated() ? r->FieldSize(message, f) : 1;
    for (int i = 0; i < n; ++i) {
      const int index = f->is_repeated() ? i : -1;
      path->push_back({f->name(), index});
      double value = 0;
      bool numeric = true, is_float = false;
      switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_MESSAGE: {
          const Message& sub = f->is_repeated() ? r->GetRepeatedMessage(message, f, i)
                                                : r->GetMessage(message, f);
          if (absl::Status s = Walk(sub, where, path); !s.ok()) return s;
          numeric = false;
          break;
        }
        case FieldDescriptor::CPPTYPE_DOUBLE:
          value = f->is_repeated() ? r->GetRepeatedDouble(message, f, i) : r->GetDouble(message, f);
          is_float = true;
          break;
        case FieldDescriptor::CPPTYPE_FLOAT:
          value = f->is_repeated() ? r->GetRepeatedFloat(message, f, i) : r->GetFloat(message, f);
          is_float = true;
          break;
        case FieldDescriptor::CPPTYPE_INT32:
          value = f->is_repeated() ? r->GetRepeatedInt32(message, f, i) : r->GetInt32(message, f);
          break;
        case FieldDescriptor::CPPTYPE_INT64:
          value = double(f->is_repeated() ? r->GetRepeatedInt64(message, f, i) : r->GetInt64(message, f));
          break;
        case FieldDescriptor::CPPTYPE_UINT32:
          value = f->is_repeated() ? r->GetRepeatedUInt32(message, f, i) : r->GetUInt32(message, f);
          break;
        case FieldDescriptor::CPPTYPE_UINT64:
          value = double(f->is_repeated() ? r->GetRepeatedUInt64(message, f, i) : r->GetUInt64(message, f));
          break;
        default:
          numeric = false;
      }
      if (numeric) {
        if (std::string why = Problem(*f, value, is_float); !why.empty()) {
          return absl::InvalidArgumentError(absl::StrCat(where.Where(*path), ": ", why));
        }
      }
      path->pop_back();
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status CheckFieldRanges(const Message& message, const SourceLocator& where) {
  FieldPath path;
  return Walk(message, where, &path);
}

}  // namespace juggle
