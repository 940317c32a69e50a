#include "render/image.h"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "absl/strings/str_cat.h"

namespace juggle {
namespace {

void AppendU32(std::string* out, uint32_t v) {
  const char b[4] = {static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                     static_cast<char>(v >> 8), static_cast<char>(v)};
  out->append(b, 4);
}

void AppendChunk(std::string* out, const char type[4], const std::string& data) {
  AppendU32(out, static_cast<uint32_t>(data.size()));
  const size_t type_at = out->size();
  out->append(type, 4);
  out->append(data);
  const uint32_t crc = crc32(crc32(0L, Z_NULL, 0),
                             reinterpret_cast<const Bytef*>(out->data() + type_at),
                             static_cast<uInt>(4 + data.size()));
  AppendU32(out, crc);
}

int Paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  return pb <= pc ? b : c;
}

absl::Status ErrnoStatus(const std::string& what, const std::string& path, int err) {
  const std::string msg = absl::StrCat("cannot ", what, " ", path, ": ", std::strerror(err));
  if (err == EACCES || err == EPERM || err == EROFS) return absl::PermissionDeniedError(msg);
  if (err == ENOENT || err == ENOTDIR) return absl::NotFoundError(msg);
  return absl::InternalError(msg);
}

}  // namespace

absl::StatusOr<std::string> EncodePng(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3) {
    return absl::InvalidArgumentError("EncodePng: empty or inconsistent image");
  }
  // Filter each row with the PNG filter (0 none, 1 sub, 2 up, 3 average, 4 Paeth) that
  // minimises the sum of absolute signed residuals (the usual heuristic, libpng's default).
  const size_t stride = static_cast<size_t>(image.width) * 3;
  std::string raw;
  raw.reserve((stride + 1) * image.height);
  std::vector<uint8_t> candidate[5];
  for (auto& c : candidate) c.resize(stride);
  const std::vector<uint8_t> zero_row(stride, 0);
  for (int y = 0; y < image.height; ++y) {
    const uint8_t* row = image.rgb.data() + y * stride;
    const uint8_t* up = y > 0 ? row - stride : zero_row.data();
    long best_cost = -1;
    int best = 0;
    for (int f = 0; f < 5; ++f) {
      long cost = 0;
      for (size_t i = 0; i < stride; ++i) {
        const int a = i >= 3 ? row[i - 3] : 0;
        const int b = up[i];
        const int c = i >= 3 ? up[i - 3] : 0;
        int predictor = 0;
        switch (f) {
          case 1: predictor = a; break;
          case 2: predictor = b; break;
          case 3: predictor = (a + b) / 2; break;
          case 4: predictor = Paeth(a, b, c); break;
          default: break;
        }
        const uint8_t v = static_cast<uint8_t>(row[i] - predictor);
        candidate[f][i] = v;
        cost += v < 128 ? v : 256 - v;
      }
      if (best_cost < 0 || cost < best_cost) {
        best_cost = cost;
        best = f;
      }
    }
    raw.push_back(static_cast<char>(best));
    raw.append(reinterpret_cast<const char*>(candidate[best].data()), stride);
  }
  uLongf compressed_size = compressBound(raw.size());
  std::string compressed(compressed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(compressed.data()), &compressed_size,
                reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 9) != Z_OK) {
    return absl::InternalError("EncodePng: zlib compress2 failed");
  }
  compressed.resize(compressed_size);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  AppendU32(&ihdr, image.width);
  AppendU32(&ihdr, image.height);
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bit, RGB, deflate, adaptive, no interlace
  AppendChunk(&png, "IHDR", ihdr);
  AppendChunk(&png, "IDAT", compressed);
  AppendChunk(&png, "IEND", "");
  return png;
}

absl::Status WriteFileBytes(const std::string& path, const std::string& bytes) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return ErrnoStatus("write", path, errno);
  const size_t written = std::fwrite(bytes.data(), 1, bytes.size(), f);
  const int write_errno = errno;
  if (std::fclose(f) != 0 || written != bytes.size()) {
    return ErrnoStatus("write", path, written != bytes.size() ? write_errno : errno);
  }
  return absl::OkStatus();
}

absl::Status WritePng(const std::string& path, const Image& image) {
  absl::StatusOr<std::string> png = EncodePng(image);
  if (!png.ok()) return png.status();
  return WriteFileBytes(path, *png);
}

Image Downscale(const Image& image, int factor) {
  Image out;
  out.Resize(image.width / factor, image.height / factor);
  const int n = factor * factor;
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int dy = 0; dy < factor; ++dy) {
          for (int dx = 0; dx < factor; ++dx) {
            sum += image.pixel(x * factor + dx, y * factor + dy)[c];
          }
        }
        out.rgb[3 * (static_cast<size_t>(y) * out.width + x) + c] =
            static_cast<uint8_t>((sum + n / 2) / n);
      }
    }
  }
  return out;
}

Image ContactSheet(const std::vector<Image>& tiles, int columns, int gap, uint8_t gap_gray) {
  const int tw = tiles[0].width, th = tiles[0].height;
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  Image sheet;
  sheet.Resize(columns * tw + (columns + 1) * gap, rows * th + (rows + 1) * gap);
  std::fill(sheet.rgb.begin(), sheet.rgb.end(), gap_gray);
  for (size_t i = 0; i < tiles.size(); ++i) {
    const int x0 = gap + static_cast<int>(i % columns) * (tw + gap);
    const int y0 = gap + static_cast<int>(i / columns) * (th + gap);
    for (int y = 0; y < th; ++y) {
      std::memcpy(&sheet.rgb[3 * (static_cast<size_t>(y0 + y) * sheet.width + x0)],
                  tiles[i].pixel(0, y), static_cast<size_t>(tw) * 3);
    }
  }
  return sheet;
}

absl::Status CheckWritable(const std::string& path) {
  if (path.empty()) return absl::InvalidArgumentError("empty output path");
  // Append mode: an existing file is neither truncated nor changed; a new one is removed again.
  const bool existed = access(path.c_str(), F_OK) == 0;
  FILE* f = std::fopen(path.c_str(), "ab");
  if (f == nullptr) return ErrnoStatus("write", path, errno);
  std::fclose(f);
  if (!existed) std::remove(path.c_str());
  return absl::OkStatus();
}

}  // namespace juggle
