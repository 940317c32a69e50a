#include "play/play_page.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "export/web_assets.h"

namespace juggle::play {

std::string PlayHtml(const ReplayLibraries& libraries, const std::string& title) {
  // A script's text must not close its element early.
  auto script = [](const std::string& text) {
    return absl::StrCat("<script>\n", absl::StrReplaceAll(text, {{"</script", "<\\/script"}}),
                        "\n</script>\n");
  };
  const std::string scripts =
      absl::StrCat(script(libraries.three_js), script(libraries.orbit_controls_js),
                   script(kSceneJs), script(kPlayJs));
  const std::string escaped_title = absl::StrReplaceAll(title, {{"&", "&amp;"}, {"<", "&lt;"}});
  return absl::StrReplaceAll(kPlayHtml, {{"<!-- juggle:title -->", escaped_title},
                                         {"<!-- juggle:scripts -->", scripts}});
}

}  // namespace juggle::play
