// The browser pages and their scripts (web/), compiled into the binary at build time (cmake/embed_files.cmake generates web_assets.cc in the build folder),
// so `juggle replay` works from any folder.
#ifndef JUGGLE_EXPORT_WEB_ASSETS_H_
#define JUGGLE_EXPORT_WEB_ASSETS_H_

namespace juggle {

extern const char kReplayHtml[];  // web/replay.html
extern const char kReplayJs[];    // web/replay.js
extern const char kSceneJs[];     // web/scene.js: the three.js scene both pages draw with
extern const char kPlayHtml[];    // web/play.html: the live page (play/play_page.h)
extern const char kPlayJs[];      // web/play.js

}  // namespace juggle

#endif  // JUGGLE_EXPORT_WEB_ASSETS_H_
