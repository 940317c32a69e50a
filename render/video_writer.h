// H.264 MP4 writer: raw RGB frames piped to Debian's `ffmpeg` (libx264, yuv420p).
//
// While a writer is open, SIGPIPE is ignored process-wide so that an ffmpeg that dies early
// turns into an error status instead of killing the process; the previous handler is restored
// by Close(). Thread-compatible.
#ifndef JUGGLE_RENDER_VIDEO_WRITER_H_
#define JUGGLE_RENDER_VIDEO_WRITER_H_

#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "render/image.h"

namespace juggle {

// Full path of `program` on $PATH, or empty if it is not there (or not executable).
std::string FindOnPath(const std::string& program);

// Single-quotes `s` for /bin/sh.
std::string ShellQuote(const std::string& s);

class VideoWriter {
 public:
  // Starts ffmpeg writing `path` at `fps`. FAILED_PRECONDITION if ffmpeg is not installed
  // ("apt-get install ffmpeg"); PERMISSION_DENIED / NOT_FOUND if `path` cannot be written;
  // INVALID_ARGUMENT for odd or non-positive sizes (yuv420p needs even width and height).
  static absl::StatusOr<std::unique_ptr<VideoWriter>> Open(const std::string& path, int width,
                                                           int height, int fps);
  // Closes the pipe if Close() was not called (errors are then lost).
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // REQUIRES: frame is width × height. INTERNAL if ffmpeg stopped reading.
  absl::Status AddFrame(const Image& frame);
  // Waits for ffmpeg; INTERNAL with its exit status if it failed.
  absl::Status Close();

  int frames() const { return frames_; }

 private:
  VideoWriter() = default;

  FILE* pipe_ = nullptr;
  std::string path_;
  int width_ = 0, height_ = 0, frames_ = 0;
  void (*old_sigpipe_)(int) = SIG_DFL;
};

}  // namespace juggle

#endif  // JUGGLE_RENDER_VIDEO_WRITER_H_
