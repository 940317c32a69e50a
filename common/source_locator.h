// Maps a field path inside a parsed text-format message to "file:line:column", so validation
// errors name the file, line and field. A config composed from a base (RunConfig.base_config)
// has one layer per file: a field is located in the file that set it. Immutable after
// construction; thread-safe to read.
#ifndef JUGGLE_COMMON_SOURCE_LOCATOR_H_
#define JUGGLE_COMMON_SOURCE_LOCATOR_H_

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "google/protobuf/descriptor.h"
#include "google/protobuf/text_format.h"

namespace juggle {

// One step of a field path: a field name and, for repeated fields, an element index (-1 for
// singular fields or "the repeated field as a whole").
struct FieldStep {
  std::string field;
  int index = -1;
};
using FieldPath = std::vector<FieldStep>;

// Renders a path as "edge[2].to".
std::string FieldPathToString(const FieldPath& path);

class SourceLocator {
 public:
  // A locator that knows only the file name (for messages built in code).
  explicit SourceLocator(std::string file);
  SourceLocator(std::string file, const google::protobuf::Descriptor* root,
                std::unique_ptr<google::protobuf::TextFormat::ParseInfoTree> tree);

  // A locator for a sub-message: paths given to it are relative to `prefix`.
  SourceLocator Nested(const FieldPath& prefix) const;

  // This file's locator over `base`'s, for a config laid over its base: a field this file
  // mentions is located here, any other in the base (the deepest mention wins; this file on a
  // tie). REQUIRES: no prefix on either (root locators).
  SourceLocator Over(const SourceLocator& base) const;

  // "file:line:col: path" for the deepest part of `path` that a file mentions; for a field
  // absent from every file, the location of its parent (or just the first file).
  std::string Where(const FieldPath& path) const;

  const std::string& file() const { return layers_.front().file; }

 private:
  struct Layer {
    std::string file;
    const google::protobuf::Descriptor* root = nullptr;
    std::shared_ptr<google::protobuf::TextFormat::ParseInfoTree> tree;
  };
  std::vector<Layer> layers_;  // this file first, then its bases
  FieldPath prefix_;
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_SOURCE_LOCATOR_H_
