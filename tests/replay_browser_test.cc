// The browser replay and the BVH export as a user runs them, with the built binary: recordings
// of both families (soccer from `juggle eval --record`, toss from `juggle toss --record`) become
// pages that headless Chromium loads without JavaScript errors and draws the character in
// (pixels of its colour in the middle of a screenshot at #t=...); `--serve` serves the same
// page; `export-bvh` writes the recording's frames; Blender (when installed) imports the BVH;
// and the commands fail clearly on missing, empty or unloadable recordings.
// Browser tests skip only when chromium is not installed (scripts/dev/install_deps.sh installs it).
#include <fcntl.h>
#include <png.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "common/http_server.h"
#include "common/testing/temp_dir.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "record/trajectory.h"
#include "tests/service_test_util.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using testing::ChildProcess;

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string LastLine(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

// Runs `argv` (argv[0] a path) in its own process group with output to `log`; kills the group
// after `seconds`. Returns the exit code (-1 on timeout or signal).
int RunProgram(const std::vector<std::string>& argv, const std::string& log, double seconds) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> args;
    std::vector<std::string> copy = argv;
    for (std::string& a : copy) args.push_back(a.data());
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  const auto until =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(int(seconds * 1000));
  int status = 0;
  while (std::chrono::steady_clock::now() < until) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(-pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return -1;
}

std::string FindProgram(const std::vector<std::string>& candidates) {
  for (const std::string& c : candidates) {
    if (::access(c.c_str(), X_OK) == 0) return c;
  }
  return "";
}

std::string Chromium() { return FindProgram({"/usr/bin/chromium", "/usr/bin/chromium-browser"}); }

struct Rgb {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;
  const uint8_t* at(int x, int y) const { return &pixels[3 * (size_t(y) * width + x)]; }
};

// Decodes a PNG with libpng's simplified API.
bool ReadPng(const std::string& path, Rgb* out) {
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return false;
  image.format = PNG_FORMAT_RGB;
  out->width = image.width;
  out->height = image.height;
  out->pixels.resize(PNG_IMAGE_SIZE(image));
  return png_image_finish_read(&image, nullptr, out->pixels.data(), 0, nullptr) != 0;
}

// The character's material colour (0.25, 0.45, 0.75) under any light: blue clearly above red
// and green. Nothing else in the page has it but the timeline strip at the bottom.
bool CharacterBlue(const uint8_t* p) { return p[2] > 70 && p[2] > p[0] + 45 && p[2] > p[1] + 20; }

int CountBlue(const Rgb& img, double x0, double x1, double y0, double y1) {
  int n = 0;
  for (int y = int(y0 * img.height); y < int(y1 * img.height); ++y) {
    for (int x = int(x0 * img.width); x < int(x1 * img.width); ++x) n += CharacterBlue(img.at(x, y));
  }
  return n;
}

// The page's console messages in chromium's log, less the GL driver's performance notes.
std::vector<std::string> PageConsole(const std::string& log) {
  std::vector<std::string> messages;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);) {
    if (line.find(":CONSOLE") != std::string::npos &&
        line.find("GL Driver Message") == std::string::npos) {
      messages.push_back(line);
    }
  }
  return messages;
}

class ReplayCliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = MakeTempDir("juggle_replay_"); }
  void TearDown() override {
    if (!HasFailure()) std::system(("rm -rf " + dir_).c_str());
    else std::fprintf(stderr, "files kept in %s\n", dir_.c_str());
  }
  // `juggle <args>`: returns the exit code; output_ holds everything it printed.
  int Juggle(const std::vector<std::string>& args, double seconds = 120) {
    const std::string log = dir_ + "/juggle" + std::to_string(runs_++) + ".log";
    ChildProcess p(args, log);
    const int code = p.Wait(seconds);
    output_ = ReadText(log);
    return code;
  }
  std::string SoccerRecording() {
    const std::string path = dir_ + "/soccer.traj";
    EXPECT_EQ(Juggle({"eval", "--zero-action", "--config=configs/right_foot.textproto",
                      "--episodes=2", "--record=" + path}), 0) << output_;
    return path;
  }
  std::string TossRecording() {
    const std::string path = dir_ + "/toss.traj";
    EXPECT_EQ(Juggle({"toss", "--zero-action", "--pattern=3", "--max-throws=6",
                      "--record=" + path}), 0) << output_;
    return path;
  }
  // Screenshot of `html` at `fragment` (800×600); returns chromium's log.
  std::string Screenshot(const std::string& html, const std::string& fragment,
                         const std::string& png) {
    const std::string log = dir_ + "/chromium.log";
    const int code = RunProgram(
        {Chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
         "--enable-unsafe-swiftshader", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run",
         "--user-data-dir=" + dir_ + "/profile", "--window-size=800,600", "--hide-scrollbars",
         "--virtual-time-budget=5000", "--enable-logging=stderr", "--v=0",
         "--screenshot=" + png, "file://" + html + "#" + fragment},
        log, 120);
    EXPECT_EQ(code, 0) << ReadText(log);
    return ReadText(log);
  }
  void ExpectLoadsAndShowsTheCharacter(const std::string& trajectory, const std::string& name) {
    if (Chromium().empty()) GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
    const std::string html = dir_ + "/" + name + ".html";
    ASSERT_EQ(Juggle({"replay", "--trajectory=" + trajectory, "--out=" + html}), 0) << output_;
    EXPECT_THAT(LastLine(output_), HasSubstr("out=" + html));
    const std::string png = dir_ + "/" + name + ".png";
    const std::string log = Screenshot(html, "t=0.3", png);
    // The page's script ran to its end, and the console holds nothing else: headless chromium
    // logs every console message (log, warn, error, uncaught exceptions) as INFO:CONSOLE; the
    // only others allowed are the GL driver's ReadPixels notes about the screenshot itself.
    EXPECT_THAT(PageConsole(log), ::testing::ElementsAre(HasSubstr("juggle replay ready")));
    Rgb img;
    ASSERT_TRUE(ReadPng(png, &img)) << png;
    ASSERT_EQ(img.width, 800);
    ASSERT_EQ(img.height, 600);
    // The follow camera centres the character: its colour in the middle, none at the sides.
    EXPECT_GT(CountBlue(img, 0.3, 0.7, 0.1, 0.75), 500);
    EXPECT_EQ(CountBlue(img, 0.0, 0.12, 0.25, 0.75), 0);
    EXPECT_EQ(CountBlue(img, 0.88, 1.0, 0.1, 0.75), 0);
  }

  std::string dir_, output_;
  int runs_ = 0;
};

TEST_F(ReplayCliTest, SoccerPageLoadsWithoutErrorsAndShowsTheCharacter) {
  ExpectLoadsAndShowsTheCharacter(SoccerRecording(), "soccer");
}

TEST_F(ReplayCliTest, TossPageLoadsWithoutErrorsAndShowsTheArms) {
  ExpectLoadsAndShowsTheCharacter(TossRecording(), "toss");
}

TEST_F(ReplayCliTest, ServeServesTheSamePageOnLoopback) {
  const std::string trajectory = TossRecording();
  const std::string html = dir_ + "/toss.html";
  ASSERT_EQ(Juggle({"replay", "--trajectory=" + trajectory, "--out=" + html}), 0) << output_;
  const std::string log = dir_ + "/serve.log";
  ChildProcess server({"replay", "--trajectory=" + trajectory, "--serve=0"}, log);
  std::smatch port;
  std::string text;
  const std::regex url("url=http://127.0.0.1:(\\d+)/");
  for (int i = 0; i < 600 && !std::regex_search(text, port, url); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    text = ReadText(log);
  }
  ASSERT_FALSE(port.empty()) << text;
  absl::StatusOr<std::string> page = HttpGet(std::stoi(port[1]), "/");
  ASSERT_TRUE(page.ok()) << page.status();
  EXPECT_TRUE(*page == ReadText(html));
  EXPECT_THAT(*page, HasSubstr("juggle replay ready"));
  server.Kill(SIGINT);
  EXPECT_EQ(server.Wait(10), 0);
}

TEST_F(ReplayCliTest, ExportBvhWritesOneFramePerSampleOfTheEpisodeAndTheBallsCsv) {
  const std::string trajectory = SoccerRecording();
  absl::StatusOr<Trajectory> t = ReadTrajectory(trajectory);
  ASSERT_TRUE(t.ok()) << t.status();
  int samples = 0;
  for (int i = 0; i < t->num_samples(); ++i) samples += t->episode(i) == 1;
  const std::string bvh = dir_ + "/motion.bvh";
  ASSERT_EQ(Juggle({"export-bvh", "--trajectory=" + trajectory, "--out=" + bvh, "--episode=1"}), 0)
      << output_;
  const std::string last = LastLine(output_);
  EXPECT_THAT(last, HasSubstr("frames=" + std::to_string(samples) + " frame_time=0.020000"));
  EXPECT_THAT(last, HasSubstr("balls=" + dir_ + "/motion.balls.csv"));
  const std::string text = ReadText(bvh);
  EXPECT_THAT(text, HasSubstr("Frames: " + std::to_string(samples) + "\nFrame Time: 0.020000\n"));
  const std::string csv = ReadText(dir_ + "/motion.balls.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), samples + 1);
}

TEST_F(ReplayCliTest, TossRecordingsExportTheArms) {
  const std::string trajectory = TossRecording();
  const std::string bvh = dir_ + "/toss.bvh";
  ASSERT_EQ(Juggle({"export-bvh", "--trajectory=" + trajectory, "--out=" + bvh}), 0) << output_;
  EXPECT_THAT(LastLine(output_), HasSubstr("family=toss"));
  EXPECT_THAT(LastLine(output_), HasSubstr("joints=8 channels=27"));
  EXPECT_THAT(ReadText(bvh), HasSubstr("JOINT right_forearm"));
}

TEST_F(ReplayCliTest, BlenderImportsTheBvhWithItsFrameRange) {
  const std::string blender = FindProgram({"/usr/bin/blender"});
  if (blender.empty()) GTEST_SKIP() << "blender is not installed (apt-get install blender)";
  // Debian 12's Blender 3.4.1 importer opens the file with mode 'rU', which Python 3.11 (its
  // interpreter) rejects; the script gives the importer's module an open() without the 'U'.
  const std::string script_head =
      "import bpy, builtins\n"
      "import io_anim_bvh.import_bvh as importer\n"
      "importer.open = lambda f, mode='r', *a, **k: builtins.open(f, mode.replace('U', ''), "
      "*a, **k)\n";
  // Prints the imported action's frame range, the bones, the scene's frame rate and the
  // fewest and most keys of any rotation curve.
  const std::string script_tail =
      "arm = bpy.context.object\n"
      "action = arm.animation_data.action\n"
      "keys = [len(c.keyframe_points) for c in action.fcurves if 'rotation' in c.data_path]\n"
      "s = bpy.context.scene\n"
      "print('BVH_RANGE', int(action.frame_range[0]), int(action.frame_range[1]), "
      "len(arm.data.bones), round(s.render.fps / s.render.fps_base, 3), min(keys), max(keys))\n";
  struct Case {
    std::string trajectory;
    int episode;
    int bones;
    const char* fps;
  };
  const Case cases[] = {{TossRecording(), 0, 8, "100.0"}, {SoccerRecording(), 1, 13, "50.0"}};
  for (const Case& c : cases) {
    absl::StatusOr<Trajectory> t = ReadTrajectory(c.trajectory);
    ASSERT_TRUE(t.ok()) << t.status();
    int frames = 0;
    for (int i = 0; i < t->num_samples(); ++i) frames += t->episode(i) == c.episode;
    const std::string bvh = c.trajectory + ".bvh";
    ASSERT_EQ(Juggle({"export-bvh", "--trajectory=" + c.trajectory, "--out=" + bvh,
                      "--episode=" + std::to_string(c.episode)}), 0) << output_;
    const std::string script = script_head + "bpy.ops.import_anim.bvh(filepath='" + bvh +
                               "', update_scene_fps=True)\n" + script_tail;
    const std::string log = bvh + ".blender.log";
    const int code =
        RunProgram({blender, "-b", "--factory-startup", "--python-expr", script}, log, 300);
    const std::string out = ReadText(log);
    ASSERT_EQ(code, 0) << out;
    // Blender numbers frames from 1; End Sites are not bones; every rotation curve (root and
    // joints, three Euler angles each) has a key per frame.
    const std::string n = std::to_string(frames);
    EXPECT_THAT(out, HasSubstr(absl::StrCat("BVH_RANGE 1 ", n, " ", c.bones, " ", c.fps, " ", n,
                                            " ", n)))
        << out;
  }
}

TEST_F(ReplayCliTest, CommandsFailClearlyOnMissingEmptyAndUnloadableRecordings) {
  for (const char* command : {"replay", "export-bvh"}) {
    EXPECT_EQ(Juggle({command, "--trajectory=" + dir_ + "/missing.traj"}), 1);
    EXPECT_THAT(output_, HasSubstr("missing.traj"));
  }
  // A recording with no samples.
  TrajectoryBuilder empty("toss", "configs/toss_catch.textproto", 0.01, 21, {"running"}, {});
  ASSERT_TRUE(WriteTrajectory(empty.trajectory(), dir_ + "/empty.traj").ok());
  EXPECT_EQ(Juggle({"export-bvh", "--trajectory=" + dir_ + "/empty.traj"}), 1);
  EXPECT_THAT(output_, HasSubstr("the recording has no samples: nothing to export"));
  EXPECT_EQ(Juggle({"replay", "--trajectory=" + dir_ + "/empty.traj"}), 1);
  EXPECT_THAT(output_, HasSubstr("the recording has no samples: nothing to replay"));
  // A recording whose config is gone.
  TrajectoryBuilder orphan("toss", "configs/deleted.textproto", 0.01, 21, {"running"}, {});
  const double qpos[21] = {};
  orphan.Append(0, 0, 0, Outcome::kRunning, nullptr, qpos);
  ASSERT_TRUE(WriteTrajectory(orphan.trajectory(), dir_ + "/orphan.traj").ok());
  EXPECT_EQ(Juggle({"export-bvh", "--trajectory=" + dir_ + "/orphan.traj",
                    "--out=" + dir_ + "/o.bvh"}), 1);
  EXPECT_THAT(output_, HasSubstr("the recording's config configs/deleted.textproto cannot be loaded"));
  EXPECT_EQ(Juggle({"replay", "--trajectory=" + dir_ + "/orphan.traj",
                    "--out=" + dir_ + "/o.html"}), 1);
  EXPECT_THAT(output_, HasSubstr("configs/deleted.textproto cannot be loaded"));
  // A recording of another model than its config's.
  TrajectoryBuilder other("soccer_juggle", "configs/toss_catch.textproto", 0.01, 21, {"running"}, {});
  other.Append(0, 0, 0, Outcome::kRunning, nullptr, qpos);
  ASSERT_TRUE(WriteTrajectory(other.trajectory(), dir_ + "/other.traj").ok());
  EXPECT_EQ(Juggle({"export-bvh", "--trajectory=" + dir_ + "/other.traj",
                    "--out=" + dir_ + "/x.bvh"}), 1);
  EXPECT_THAT(output_, HasSubstr("recorded with family soccer_juggle and nq 21, but config"));
  // An episode the recording does not have.
  EXPECT_EQ(Juggle({"export-bvh", "--trajectory=" + SoccerRecording(), "--episode=5",
                    "--out=" + dir_ + "/y.bvh"}), 1);
  EXPECT_THAT(output_, HasSubstr("no episode 5 (episodes 0..1)"));
}

TEST_F(ReplayCliTest, NewCommandsHaveHelp) {
  for (const char* command : {"replay", "export-bvh"}) {
    EXPECT_EQ(Juggle({command, "--help"}), 0);
    EXPECT_THAT(output_, HasSubstr("--trajectory"));
  }
}

}  // namespace
}  // namespace juggle
