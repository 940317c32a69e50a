// RGB images and the small amount of image work the renderer needs: PNG encoding (libpng),
// box downscaling and contact sheets.
#ifndef JUGGLE_RENDER_IMAGE_H_
#define JUGGLE_RENDER_IMAGE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace juggle {

// 8-bit RGB, rows top to bottom: rgb[3 * (y * width + x) + c].
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;

  void Resize(int w, int h) {
    width = w;
    height = h;
    rgb.assign(static_cast<size_t>(w) * h * 3, 0);
  }
  const uint8_t* pixel(int x, int y) const {
    return &rgb[3 * (static_cast<size_t>(y) * width + x)];
  }
};

// PNG bytes of `image` (8-bit RGB, adaptive per-row filters, zlib level 9).
// INVALID_ARGUMENT for an empty or inconsistent image.
absl::StatusOr<std::string> EncodePng(const Image& image);

// EncodePng + WriteFile (common/file_io.h: errors name the path and the reason).
absl::Status WritePng(const std::string& path, const Image& image);

// Averages factor×factor blocks (the last partial row/column is dropped). REQUIRES: factor >= 1.
Image Downscale(const Image& image, int factor);

// Tiles of equal size on a grid of `columns`, row-major, separated by `gap` pixels of `gap_gray`.
// REQUIRES: tiles non-empty and all the same size; columns >= 1.
Image ContactSheet(const std::vector<Image>& tiles, int columns, int gap = 2,
                   uint8_t gap_gray = 255);

}  // namespace juggle

#endif  // JUGGLE_RENDER_IMAGE_H_
