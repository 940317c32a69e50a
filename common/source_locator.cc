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

SourceLocator::SourceLocator(std::string file) {
  layers_.push_back({std::move(file), nullptr, nullptr});
}

SourceLocator::SourceLocator(std::string file, const Descriptor* root,
                             std::unique_ptr<TextFormat::ParseInfoTree> tree) {
  layers_.push_back({std::move(file), root, std::move(tree)});
}

SourceLocator SourceLocator::Nested(const FieldPath& prefix) const {
  SourceLocator nested = *this;
  nested.prefix_.insert(nested.prefix_.end(), prefix.begin(), prefix.end());
  return nested;
}

SourceLocator SourceLocator::Over(const SourceLocator& base) const {
  SourceLocator layered = *this;
  layered.layers_.insert(layered.layers_.end(), base.layers_.begin(), base.layers_.end());
  return layered;
}

std::string SourceLocator::Where(const FieldPath& relative) const {
  FieldPath path = prefix_;
  path.insert(path.end(), relative.begin(), relative.end());
  // Per file: how many steps of the path it mentions, and where the last one is.
  const std::string* file = &layers_.front().file;
  int best_depth = 0, line = -1, column = -1;
  for (const Layer& layer : layers_) {
    if (layer.tree == nullptr || layer.root == nullptr) continue;
    const TextFormat::ParseInfoTree* tree = layer.tree.get();
    const Descriptor* desc = layer.root;
    int depth = 0, l = -1, c = -1;
    for (const FieldStep& step : path) {
      if (tree == nullptr || desc == nullptr) break;
      const FieldDescriptor* field = desc->FindFieldByName(step.field);
      if (field == nullptr) break;
      const int index = field->is_repeated() ? (step.index >= 0 ? step.index : 0) : -1;
      const auto loc = tree->GetLocation(field, index);
      if (loc.line < 0) break;
      ++depth;
      l = loc.line;
      c = loc.column;
      if (field->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) break;
      tree = tree->GetTreeForNested(field, index);
      desc = field->message_type();
    }
    if (depth > best_depth) {
      best_depth = depth;
      file = &layer.file;
      line = l;
      column = c;
    }
  }
  std::string where = *file;
  if (line >= 0) absl::StrAppend(&where, ":", line + 1, ":", column + 1);
  const std::string field = FieldPathToString(relative);
  if (!field.empty()) absl::StrAppend(&where, ": ", field);
  return where;
}

}  // namespace juggle
