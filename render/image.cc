#include "render/image.h"

#include <unistd.h>
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <csetjmp>
#include <cstdlib>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "common/file_io.h"

namespace juggle {
namespace {

// libpng's write callback: appends to the std::string behind the io pointer.
void AppendToString(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data),
                                                         length);
}
void NoFlush(png_structp) {}

// libpng reports errors through longjmp; the message is kept for the status.
void OnPngError(png_structp png, png_const_charp message) {
  *static_cast<std::string*>(png_get_error_ptr(png)) = message;
  png_longjmp(png, 1);
}
void OnPngWarning(png_structp, png_const_charp) {}

}  // namespace

absl::StatusOr<std::string> EncodePng(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3) {
    return absl::InvalidArgumentError("EncodePng: empty or inconsistent image");
  }
  std::string png_bytes;
  std::string error;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, OnPngError,
                                            OnPngWarning);
  if (png == nullptr) return absl::InternalError("EncodePng: png_create_write_struct failed");
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> rows(image.height);
  // Nothing with a destructor may be created between setjmp and a longjmp back to it.
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return absl::InternalError(absl::StrCat("EncodePng: libpng: ", error));
  }
  png_set_write_fn(png, &png_bytes, AppendToString, NoFlush);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // Adaptive per-row filters (libpng chooses among all five by the minimum sum of absolute
  // differences) and zlib level 9.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_ALL_FILTERS);
  png_set_compression_level(png, 9);
  for (int y = 0; y < image.height; ++y) {
    rows[y] = const_cast<png_bytep>(image.rgb.data() + static_cast<size_t>(y) * image.width * 3);
  }
  png_set_rows(png, info, rows.data());
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return png_bytes;
}

absl::Status WritePng(const std::string& path, const Image& image) {
  absl::StatusOr<std::string> png = EncodePng(image);
  if (!png.ok()) return png.status();
  return WriteFile(path, *png);
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

}  // namespace juggle
