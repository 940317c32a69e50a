#include "common/flat_parameters.h"

#include <algorithm>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace juggle {
namespace {

constexpr char kMagic[4] = {'J', 'G', 'L', 'P'};
constexpr uint32_t kFormat = 1;

template <typename T>
void Put(std::string* out, T v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// Reads sequentially from a byte buffer; every read reports truncation.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  template <typename T>
  bool Get(T* v) {
    if (pos_ + sizeof(T) > bytes_.size()) return false;
    std::memcpy(v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  bool GetBytes(size_t n, std::string* s) {
    if (pos_ + n > bytes_.size()) return false;
    s->assign(bytes_.data() + pos_, n);
    pos_ += n;
    return true;
  }
  bool GetFloats(size_t n, std::vector<float>* v) {
    if (n > (bytes_.size() - pos_) / sizeof(float)) return false;
    v->resize(n);
    std::memcpy(v->data(), bytes_.data() + pos_, n * sizeof(float));
    pos_ += n * sizeof(float);
    return true;
  }
  bool done() const { return pos_ == bytes_.size(); }
  size_t remaining() const { return bytes_.size() - pos_; }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

std::string ShapeString(const std::vector<int64_t>& shape) {
  return absl::StrCat("[", absl::StrJoin(shape, ", "), "]");
}

}  // namespace

absl::StatusOr<FlatParameters> FlatParameters::Create(int64_t version,
                                                      std::vector<TensorSpec> layout,
                                                      std::vector<float> values) {
  FlatParameters p;
  int64_t total = 0;
  for (const TensorSpec& t : layout) {
    p.offsets_.push_back(total);
    total += t.numel();
  }
  if (total != static_cast<int64_t>(values.size())) {
    return absl::InvalidArgumentError(absl::StrCat("layout needs ", total, " values, got ",
                                                   values.size()));
  }
  p.version_ = version;
  p.layout_ = std::move(layout);
  p.values_ = std::move(values);
  return p;
}

absl::StatusOr<const float*> FlatParameters::Find(const std::string& name,
                                                  const std::vector<int64_t>& shape) const {
  for (size_t i = 0; i < layout_.size(); ++i) {
    if (layout_[i].name != name) continue;
    if (layout_[i].shape != shape) {
      return absl::InvalidArgumentError(absl::StrCat("tensor '", name, "' has shape ",
                                                     ShapeString(layout_[i].shape),
                                                     ", expected ", ShapeString(shape)));
    }
    return values_.data() + offsets_[i];
  }
  return absl::NotFoundError(absl::StrCat("no tensor '", name, "' in the parameters"));
}

std::string FlatParameters::Serialize() const {
  std::string out(kMagic, 4);
  Put<uint32_t>(&out, kFormat);
  Put<int64_t>(&out, version_);
  Put<uint32_t>(&out, static_cast<uint32_t>(layout_.size()));
  for (const TensorSpec& t : layout_) {
    Put<uint32_t>(&out, static_cast<uint32_t>(t.name.size()));
    out += t.name;
    Put<uint8_t>(&out, 0);  // dtype: float32
    Put<uint8_t>(&out, static_cast<uint8_t>(t.shape.size()));
    for (int64_t d : t.shape) Put<int64_t>(&out, d);
  }
  Put<uint64_t>(&out, values_.size());
  out.append(reinterpret_cast<const char*>(values_.data()), values_.size() * sizeof(float));
  return out;
}

absl::StatusOr<FlatParameters> FlatParameters::Deserialize(std::string_view bytes) {
  auto corrupt = [](const std::string& what) {
    return absl::DataLossError(absl::StrCat("flat parameters: ", what));
  };
  Reader r(bytes);
  std::string magic;
  uint32_t format = 0, count = 0;
  int64_t version = 0;
  if (!r.GetBytes(4, &magic) || magic != std::string(kMagic, 4)) return corrupt("bad magic");
  if (!r.Get(&format) || format != kFormat) return corrupt("unsupported format");
  if (!r.Get(&version) || !r.Get(&count)) return corrupt("truncated header");
  // Claimed sizes are checked against the bytes before anything is allocated from them: a
  // tensor's entry takes at least 6 bytes, and no tensor holds more floats than the input.
  constexpr size_t kMinEntryBytes = 6;
  if (count > r.remaining() / kMinEntryBytes) {
    return corrupt(absl::StrCat(count, " tensors cannot fit in ", r.remaining(), " bytes"));
  }
  const int64_t max_values = static_cast<int64_t>(bytes.size() / sizeof(float));
  std::vector<TensorSpec> layout(count);
  for (TensorSpec& t : layout) {
    uint32_t len = 0;
    uint8_t dtype = 0, ndim = 0;
    if (!r.Get(&len) || len > 4096 || !r.GetBytes(len, &t.name) || !r.Get(&dtype) ||
        !r.Get(&ndim)) {
      return corrupt("truncated layout");
    }
    if (dtype != 0) return corrupt(absl::StrCat("tensor '", t.name, "' has unknown dtype"));
    t.shape.resize(ndim);
    // The product of the non-zero dimensions (saturating at max_values + 1) bounds every
    // partial product numel() computes, so numel() cannot overflow.
    int64_t nonzero_product = 1;
    for (int64_t& d : t.shape) {
      if (!r.Get(&d) || d < 0) return corrupt("truncated or negative shape");
      if (d == 0) continue;
      nonzero_product = nonzero_product > max_values / d ? max_values + 1 : nonzero_product * d;
    }
    if (nonzero_product > max_values) {
      return corrupt(absl::StrCat("tensor '", t.name, "' is larger than the data"));
    }
  }
  uint64_t n = 0;
  std::vector<float> values;
  if (!r.Get(&n) || !r.GetFloats(n, &values)) return corrupt("truncated values");
  if (!r.done()) return corrupt("trailing bytes");
  absl::StatusOr<FlatParameters> p = Create(version, std::move(layout), std::move(values));
  if (!p.ok()) return corrupt(std::string(p.status().message()));
  return p;
}

}  // namespace juggle
