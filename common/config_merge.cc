#include "common/config_merge.h"

#include <filesystem>
#include <memory>
#include <vector>

#include "absl/strings/match.h"

namespace juggle {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

void MergeOver(const Message& derived, Message* base) {
  const Reflection* from = derived.GetReflection();
  const Reflection* to = base->GetReflection();
  std::vector<const FieldDescriptor*> fields;
  from->ListFields(derived, &fields);
  for (const FieldDescriptor* field : fields) {
    if (field->is_repeated()) {
      to->ClearField(base, field);
      continue;  // copied below with the others
    }
    if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      MergeOver(from->GetMessage(derived, field), to->MutableMessage(base, field));
    }
  }
  // Scalars, strings, enums and the (cleared) repeated fields: MergeFrom of a copy holding
  // only them sets scalars and appends repeated fields to the now empty ones.
  std::unique_ptr<Message> rest(derived.New());
  rest->CopyFrom(derived);
  const Reflection* r = rest->GetReflection();
  for (const FieldDescriptor* field : fields) {
    if (!field->is_repeated() && field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      r->ClearField(rest.get(), field);
    }
  }
  base->MergeFrom(*rest);
}

namespace {

// Whether `type` or a singular sub-message of it has a `*_file` field with a default.
bool NamesFilesByDefault(const google::protobuf::Descriptor* type, int depth = 0) {
  if (depth > 8) return false;  // recursive types
  for (int i = 0; i < type->field_count(); ++i) {
    const FieldDescriptor* f = type->field(i);
    if (f->is_repeated()) continue;
    if (f->cpp_type() == FieldDescriptor::CPPTYPE_STRING && absl::EndsWith(f->name(), "_file") &&
        f->has_default_value() && !f->default_value_string().empty()) {
      return true;
    }
    if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE && f->containing_oneof() == nullptr &&
        NamesFilesByDefault(f->message_type(), depth + 1)) {
      return true;
    }
  }
  return false;
}

}  // namespace

void RebaseFileNames(const std::string& from_dir_name, const std::string& to_dir_name,
                     Message* message) {
  std::string from_dir = from_dir_name, to_dir = to_dir_name;
  if (std::filesystem::path(from_dir).is_absolute() != std::filesystem::path(to_dir).is_absolute()) {
    // One absolute, one relative (a base named by absolute path): no relative path joins them
    // until both are absolute, from the working directory.
    from_dir = std::filesystem::absolute(from_dir).string();
    to_dir = std::filesystem::absolute(to_dir).string();
  }
  if ((std::filesystem::path(from_dir) / "x").lexically_normal() ==
      (std::filesystem::path(to_dir) / "x").lexically_normal()) {
    return;  // the same folder: nothing to rewrite (and defaults stay unset)
  }
  const Reflection* r = message->GetReflection();
  const google::protobuf::Descriptor* d = message->GetDescriptor();
  for (int i = 0; i < d->field_count(); ++i) {
    const FieldDescriptor* field = d->field(i);
    if (field->is_repeated()) {
      if (field->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) continue;
      for (int k = 0; k < r->FieldSize(*message, field); ++k) {
        RebaseFileNames(from_dir, to_dir, r->MutableRepeatedMessage(message, field, k));
      }
    } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      // An absent message whose defaults name files is made present (another case of a oneof
      // is left absent): its defaults must keep naming the base folder's files.
      if (r->HasField(*message, field) ||
          (field->containing_oneof() == nullptr && NamesFilesByDefault(field->message_type()))) {
        RebaseFileNames(from_dir, to_dir, r->MutableMessage(message, field));
      }
    } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_STRING &&
               absl::EndsWith(field->name(), "_file")) {
      const std::string name = r->GetString(*message, field);  // the default when unset
      if (name.empty() || name[0] == '/') continue;
      if (field->containing_oneof() != nullptr && !r->HasField(*message, field)) continue;
      const std::filesystem::path target = (std::filesystem::path(from_dir) / name).lexically_normal();
      r->SetString(message, field,
                   target.lexically_relative(std::filesystem::path(to_dir).lexically_normal())
                       .string());
    }
  }
}

}  // namespace juggle
