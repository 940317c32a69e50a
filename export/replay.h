// The browser replay (`juggle replay`): a recording turned into one self-contained HTML page
// that plays it in 3D with three.js — no physics in the page. Everything the page draws is
// computed here: per-sample world transforms of the bodies (mj_forward of each sample's qpos),
// the drawable geoms of the model, ball contacts per sample, and the changes of every
// categorical channel (soccer: node; toss: hand and ball modes). docs/replay_and_export.md.
// Pure functions; thread-compatible.
#ifndef JUGGLE_EXPORT_REPLAY_H_
#define JUGGLE_EXPORT_REPLAY_H_

#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "record/trajectory.h"

namespace juggle {

// A geom the page draws, in its body's frame.
struct ReplayGeom {
  std::string name;   // geom name, or "" if unnamed
  int body = -1;      // index into ReplayData::body_ids; -1: fixed in the world
  std::string type;   // "plane", "sphere", "capsule", "ellipsoid", "cylinder", "box", "mesh"
  double size[3] = {0, 0, 0};  // MuJoCo's geom_size (half-lengths, radii)
  // A mesh's vertices (x y z, in the geom's frame) and triangles (three vertex indices each;
  // MuJoCo's convex hull when the model gives vertices only); empty for other types.
  std::vector<float> vertices;
  std::vector<int> faces;
  double pos[3] = {0, 0, 0};   // in the body frame (world frame when body == -1)
  double quat[4] = {1, 0, 0, 0};  // w x y z
  float rgba[4] = {1, 1, 1, 1};   // the material's colour if it has one, else the geom's
};

// A ball touching something at a frame.
struct ReplayContact {
  int frame = 0;
  std::string ball;   // ball body name
  std::string other;  // the other body's name ("world" bodies: the geom's name, e.g. floor)
};

// A categorical channel taking a new value (within an episode), or an episode's first frame.
struct ReplayEvent {
  int frame = 0;
  std::string channel;  // channel name; "episode" for an episode's first frame
  std::string label;    // the new label (the episode number for "episode")
};

// What a model's page draws: the bodies that carry drawable geoms (their transforms change),
// the geoms, and the body the camera follows (the character's root).
struct ReplayScene {
  std::vector<int> body_ids;             // model bodies with per-frame transforms
  std::vector<std::string> body_names;
  int follow = 0;                        // index into body_ids: the character's root
  std::vector<ReplayGeom> geoms;
  int skipped_geoms = 0;                 // height fields, invisible geoms
};
ReplayScene BuildReplayScene(const mjModel* model);
// The scene's geoms as a JSON array (the page's "geoms", web/scene.js).
std::string ReplayGeomsJson(const std::vector<ReplayGeom>& geoms);

struct ReplayData {
  std::string family, config_path;
  double control_dt = 0;
  std::vector<int> body_ids;             // model bodies with per-frame transforms
  std::vector<std::string> body_names;
  int follow = 0;                        // index into body_ids: the character's root
  std::vector<ReplayGeom> geoms;
  int skipped_geoms = 0;                 // height fields, invisible geoms
  std::vector<AnnotationChannel> channels;  // the recording's, in its order
  std::vector<int> samples;              // recording sample of each frame
  std::vector<double> time;              // [frames] s, from the first frame
  std::vector<double> values;            // [frames, channels]
  std::vector<double> xpos;              // [frames, bodies, 3] world positions (m)
  std::vector<double> xquat;             // [frames, bodies, 4] world orientations (w x y z)
  std::vector<ReplayContact> contacts;   // sorted by frame
  std::vector<ReplayEvent> events;       // sorted by frame

  int num_frames() const { return static_cast<int>(time.size()); }
};

// Builds the page's data from `trajectory`'s samples of `episode` (-1: every episode).
// INVALID_ARGUMENT for an empty recording, an episode it does not have, or a model whose nq
// differs from the recording's.
absl::StatusOr<ReplayData> BuildReplayData(const mjModel* model, const Trajectory& trajectory,
                                           int episode = -1);

// The data as compact JSON: numbers of transforms and times as integers in units of
// 1/`scale` (1e-4 m, 1e-4 of a unit quaternion, 0.1 ms).
std::string ReplayJson(const ReplayData& data);

// The JavaScript libraries the page embeds: three.js r111 and its OrbitControls (Debian
// libjs-three).
struct ReplayLibraries {
  std::string three_js;
  std::string orbit_controls_js;
};
constexpr char kDefaultThreeJsDir[] = "/usr/share/javascript/three";
// Reads `dir`/three.min.js and `dir`/examples/js/controls/OrbitControls.js. NOT_FOUND naming
// the file and the package (apt-get install libjs-three).
absl::StatusOr<ReplayLibraries> LoadReplayLibraries(const std::string& dir = kDefaultThreeJsDir);

// The self-contained page: web/replay.html with three.js, OrbitControls, the data and
// web/replay.js inlined (the web/ files are compiled into the binary).
std::string ReplayHtml(const ReplayData& data, const ReplayLibraries& libraries,
                       const std::string& title);

}  // namespace juggle

#endif  // JUGGLE_EXPORT_REPLAY_H_
