// The browser replay's page and script (web/replay.html, web/replay.js), compiled into the
// binary at build time (cmake/embed_files.cmake generates web_assets.cc in the build folder),
// so `juggle replay` works from any folder.
#ifndef JUGGLE_EXPORT_WEB_ASSETS_H_
#define JUGGLE_EXPORT_WEB_ASSETS_H_

namespace juggle {

extern const char kReplayHtml[];  // web/replay.html
extern const char kReplayJs[];    // web/replay.js

}  // namespace juggle

#endif  // JUGGLE_EXPORT_WEB_ASSETS_H_
