#include "render/video_writer.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "common/file_io.h"

namespace juggle {

std::string FindOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return "";
  for (absl::string_view dir : absl::StrSplit(path, ':', absl::SkipEmpty())) {
    const std::string candidate = absl::StrCat(dir, "/", program);
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

absl::StatusOr<std::unique_ptr<VideoWriter>> VideoWriter::Open(const std::string& path,
                                                               int width, int height, int fps) {
  if (width <= 0 || height <= 0 || width % 2 || height % 2 || fps <= 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "H.264 in yuv420p needs an even, positive width and height; got ", width, "x", height));
  }
  const std::string ffmpeg = FindOnPath("ffmpeg");
  if (ffmpeg.empty()) {
    return absl::FailedPreconditionError(
        "ffmpeg not found on PATH; MP4 output pipes frames to it: apt-get install ffmpeg");
  }
  if (absl::Status s = CheckWritable(path); !s.ok()) return s;

  const std::string command = absl::StrCat(
      ShellQuote(ffmpeg), " -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24 -s ",
      width, "x", height, " -r ", fps, " -i - -c:v libx264 -preset veryfast -crf 23",
      " -pix_fmt yuv420p -movflags +faststart ", ShellQuote(path));
  std::unique_ptr<VideoWriter> writer(new VideoWriter());
  writer->old_sigpipe_ = std::signal(SIGPIPE, SIG_IGN);
  writer->pipe_ = popen(command.c_str(), "w");
  if (writer->pipe_ == nullptr) {
    std::signal(SIGPIPE, writer->old_sigpipe_);
    return absl::InternalError(absl::StrCat("could not start ffmpeg: ", command));
  }
  writer->path_ = path;
  writer->width_ = width;
  writer->height_ = height;
  return writer;
}

VideoWriter::~VideoWriter() {
  if (pipe_ != nullptr) Close().IgnoreError();
}

absl::Status VideoWriter::AddFrame(const Image& frame) {
  if (pipe_ == nullptr) return absl::FailedPreconditionError("VideoWriter is closed");
  if (frame.width != width_ || frame.height != height_) {
    return absl::InvalidArgumentError(absl::StrCat("frame is ", frame.width, "x", frame.height,
                                                   ", video is ", width_, "x", height_));
  }
  if (std::fwrite(frame.rgb.data(), 1, frame.rgb.size(), pipe_) != frame.rgb.size()) {
    return absl::InternalError(
        absl::StrCat("ffmpeg stopped reading frames for ", path_, " (see its message above)"));
  }
  ++frames_;
  return absl::OkStatus();
}

absl::Status VideoWriter::Close() {
  if (pipe_ == nullptr) return absl::OkStatus();
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  std::signal(SIGPIPE, old_sigpipe_);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return absl::InternalError(absl::StrCat("ffmpeg failed writing ", path_, " (exit status ",
                                            WIFEXITED(status) ? WEXITSTATUS(status) : -1, ")"));
  }
  return absl::OkStatus();
}

}  // namespace juggle
