#include "common/source_locator.h"

#include "absl/strings/str_cat.h"

namespace juggle {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::TextFormat;

std::string FieldPathToString(const FieldPath& path) {
  std::string out;
  for (const FieldStep& step : path) {
    if (!out.empty()) out += ".";
    out += step.field;
    if (step.index >= 0) absl::StrAppend(&out, "[", step.index, "]");
  }
  return out;
}

SourceLocator::SourceLocator(std::string file) : file_(std::move(file)) {}

SourceLocator::SourceLocator(std::string file, const Descriptor* root,
                             std::unique_ptr<TextFormat::ParseInfoTree> tree)
    : file_(std::move(file)), root_(root), tree_(std::move(tree)) {}

SourceLocator SourceLocator::Nested(const FieldPath& prefix) const {
  SourceLocator nested = *this;
  nested.prefix_.insert(nested.prefix_.end(), prefix.begin(), prefix.end());
  return nested;
}

std::string SourceLocator::Where(const FieldPath& relative) const {
  FieldPath path = prefix_;
  path.insert(path.end(), relative.begin(), relative.end());
  int line = -1, column = -1;
  if (tree_ != nullptr && root_ != nullptr) {
    const TextFormat::ParseInfoTree* tree = tree_.get();
    const Descriptor* desc = root_;
    for (const FieldStep& step : path) {
      if (tree == nullptr || desc == nullptr) break;
      const FieldDescriptor* field = desc->FindFieldByName(step.field);
      if (field == nullptr) break;
      const int index = field->is_repeated() ? (step.index >= 0 ? step.index : 0) : -1;
      const auto loc = tree->GetLocation(field, index);
      if (loc.line < 0) break;
      line = loc.line;
      column = loc.column;
      if (field->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) break;
      tree = tree->GetTreeForNested(field, index);
      desc = field->message_type();
    }
  }
  std::string where = file_;
  if (line >= 0) absl::StrAppend(&where, ":", line + 1, ":", column + 1);
  const std::string field = FieldPathToString(relative);
  if (!field.empty()) absl::StrAppend(&where, ": ", field);
  return where;
}

}  // namespace juggle
