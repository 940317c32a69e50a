#include "learner/checkpoint.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/file_io.h"

namespace juggle {
namespace {

constexpr char kMagic[8] = {'J', 'G', 'L', 'C', 'K', 'P', 'T', '1'};

template <typename T>
void Put(std::string* out, T v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
bool Get(const std::string& in, size_t* pos, T* v) {
  if (*pos + sizeof(T) > in.size()) return false;
  std::memcpy(v, in.data() + *pos, sizeof(T));
  *pos += sizeof(T);
  return true;
}

}  // namespace

absl::Status WriteCheckpointFile(const std::string& path, const Sections& sections) {
  std::string payload;
  Put<uint32_t>(&payload, static_cast<uint32_t>(sections.size()));
  for (const auto& [name, bytes] : sections) {
    Put<uint32_t>(&payload, static_cast<uint32_t>(name.size()));
    payload += name;
    Put<uint64_t>(&payload, bytes.size());
    payload += bytes;
  }
  std::string file(kMagic, sizeof(kMagic));
  Put<uint64_t>(&file, payload.size());
  Put<uint64_t>(&file, Fnv1a64(payload));
  file += payload;

  return WriteFileAtomically(path, file);
}

absl::StatusOr<Sections> ReadCheckpointFile(const std::string& path) {
  absl::StatusOr<std::string> bytes = ReadFile(path);
  if (!bytes.ok()) return bytes.status();
  return ParseCheckpoint(*bytes, path);
}

absl::StatusOr<Sections> ParseCheckpoint(const std::string& in, const std::string& path) {
  auto loss = [&](const std::string& what) {
    return absl::DataLossError(absl::StrCat("checkpoint ", path, ": ", what));
  };
  if (in.size() < sizeof(kMagic) || std::memcmp(in.data(), kMagic, sizeof(kMagic)) != 0) {
    return loss("not a juggle checkpoint (bad magic)");
  }
  size_t pos = sizeof(kMagic);
  uint64_t size = 0, checksum = 0;
  if (!Get(in, &pos, &size) || !Get(in, &pos, &checksum)) return loss("truncated header");
  if (in.size() - pos != size) {
    return loss(absl::StrCat("truncated: payload has ", in.size() - pos, " of ", size, " bytes"));
  }
  const std::string payload = in.substr(pos);
  if (Fnv1a64(payload) != checksum) return loss("corrupted: checksum mismatch");
  Sections sections;
  size_t p = 0;
  uint32_t count = 0;
  if (!Get(payload, &p, &count)) return loss("truncated section table");
  // Sizes are compared with what is left, never added to the position first (no overflow).
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t name_len = 0;
    uint64_t len = 0;
    if (!Get(payload, &p, &name_len) || name_len > payload.size() - p) return loss("bad section");
    std::string name = payload.substr(p, name_len);
    p += name_len;
    if (!Get(payload, &p, &len) || len > payload.size() - p) return loss("bad section");
    if (sections.count(name)) return loss(absl::StrCat("section '", name, "' appears twice"));
    sections[name] = payload.substr(p, len);
    p += len;
  }
  if (p != payload.size()) return loss("bytes after the last section");
  return sections;
}

CheckpointDir::CheckpointDir(std::string dir, int keep) : dir_(std::move(dir)), keep_(keep) {}

std::vector<std::string> CheckpointDir::List() const {
  std::vector<std::string> names;
  if (DIR* d = ::opendir(dir_.c_str())) {
    while (dirent* e = ::readdir(d)) {
      const std::string name = e->d_name;
      if (name.rfind("ckpt-", 0) == 0 && name.size() > 10 &&
          name.compare(name.size() - 5, 5, ".jglc") == 0) {
        names.push_back(name);
      }
    }
    ::closedir(d);
  }
  std::sort(names.rbegin(), names.rend());  // zero-padded: lexical = numeric
  for (std::string& n : names) n = absl::StrCat(dir_, "/", n);
  return names;
}

absl::StatusOr<std::string> CheckpointDir::Save(int64_t iteration, const Sections& sections) {
  // Create the directory and its parents.
  for (size_t slash = dir_.find('/', 1); ; slash = dir_.find('/', slash + 1)) {
    ::mkdir(dir_.substr(0, slash).c_str(), 0755);
    if (slash == std::string::npos) break;
  }
  const std::string path = absl::StrFormat("%s/ckpt-%010d.jglc", dir_, iteration);
  if (absl::Status s = WriteCheckpointFile(path, sections); !s.ok()) return s;
  const std::vector<std::string> all = List();
  for (size_t i = keep_; i < all.size(); ++i) ::unlink(all[i].c_str());
  return path;
}

absl::StatusOr<CheckpointDir::Loaded> CheckpointDir::LoadLatest() const {
  Loaded loaded;
  for (const std::string& path : List()) {
    absl::StatusOr<Sections> s = ReadCheckpointFile(path);
    if (s.ok()) {
      loaded.path = path;
      loaded.sections = std::move(*s);
      return loaded;
    }
    loaded.skipped.push_back(std::string(s.status().message()));
  }
  std::string why = loaded.skipped.empty() ? "" : absl::StrCat(" (skipped: ", loaded.skipped[0], ")");
  return absl::NotFoundError(absl::StrCat("no readable checkpoint in ", dir_, why));
}

}  // namespace juggle
