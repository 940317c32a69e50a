#include "envs/stored_config.h"

#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/mujoco_model.h"
#include "envs/registry.h"
#include "google/protobuf/descriptor.h"
#include "google/protobuf/text_format.h"

namespace juggle {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

// The first field (as "a.b.c") of `message` that names a file the loader would read:
// base_config, or a set *_file string other than model_file. "" if there is none.
std::string FileNamedIn(const Message& message, const std::string& prefix) {
  std::vector<const FieldDescriptor*> fields;
  message.GetReflection()->ListFields(message, &fields);
  for (const FieldDescriptor* field : fields) {
    const std::string name = absl::StrCat(prefix, field->name());
    if (field->cpp_type() == FieldDescriptor::CPPTYPE_STRING &&
        (field->name() == "base_config" ||
         (absl::EndsWith(field->name(), "_file") && field->name() != "model_file"))) {
      return name;
    }
    if (field->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) continue;
    const int count = field->is_repeated()
                          ? message.GetReflection()->FieldSize(message, field)
                          : 1;
    for (int i = 0; i < count; ++i) {
      const Message& child = field->is_repeated()
                                 ? message.GetReflection()->GetRepeatedMessage(message, field, i)
                                 : message.GetReflection()->GetMessage(message, field);
      if (std::string found = FileNamedIn(child, name + "."); !found.empty()) return found;
    }
  }
  return "";
}

}  // namespace

StoredConfig StoreConfig(const LoadedConfig& config, const EnvSpec& spec) {
  StoredConfig stored;
  // The run's demonstrations live in its own demos.jgld from the first checkpoint on
  // (proto/imitation.proto): the file that seeded them is not read again.
  config::RunConfig run = config.run;
  run.mutable_imitation()->clear_initial_demos_file();
  if (run.imitation().ByteSizeLong() == 0) run.clear_imitation();
  google::protobuf::TextFormat::PrintToString(run, &stored.text);
  stored.model_mjb = SaveModel(spec.model());
  return stored;
}

absl::StatusOr<LoadedConfig> LoadStoredConfig(const StoredConfig& stored, const std::string& name,
                                              const std::string& config_path) {
  if (stored.model_mjb.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(name, ": the stored config has no model"));
  }
  // Check that nothing would be read before the loader reads it.
  config::RunConfig run;
  RETURN_IF_ERROR(ParseTextMessage(stored.text, name, &run).status());
  if (const std::string field = FileNamedIn(run, ""); !field.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        name, ": a stored config must have its files inlined, but it names one in ", field));
  }
  ASSIGN_OR_RETURN(LoadedConfig config, ParseRunConfig(stored.text, name));
  config.config_path = config_path;
  config.model_mjb = stored.model_mjb;
  return config;
}

}  // namespace juggle
