// The live page as one HTML document: web/play.html with three.js r111 and OrbitControls
// (Debian's libjs-three, read at run time: export/replay.h's LoadReplayLibraries), web/scene.js
// and web/play.js inlined (compiled into the binary: export/web_assets.h).
#ifndef JUGGLE_PLAY_PLAY_PAGE_H_
#define JUGGLE_PLAY_PLAY_PAGE_H_

#include <string>

#include "export/replay.h"

namespace juggle::play {

std::string PlayHtml(const ReplayLibraries& libraries, const std::string& title);

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_PLAY_PAGE_H_
