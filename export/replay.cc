#include "export/replay.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <tuple>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_replace.h"
#include "common/file_io.h"
#include "envs/mujoco_model.h"
#include "export/trajectory_model.h"
#include "export/web_assets.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

constexpr double kScale = 10000;

const char* GeomTypeName(int type) {
  switch (type) {
    case mjGEOM_PLANE: return "plane";
    case mjGEOM_SPHERE: return "sphere";
    case mjGEOM_CAPSULE: return "capsule";
    case mjGEOM_ELLIPSOID: return "ellipsoid";
    case mjGEOM_CYLINDER: return "cylinder";
    case mjGEOM_BOX: return "box";
    case mjGEOM_MESH: return "mesh";
    default: return nullptr;  // height fields: not drawn
  }
}

std::string Name(const mjModel* m, mjtObj type, int id) {
  const char* name = mj_id2name(m, type, id);
  return name != nullptr ? name : "";
}

// Fixed-point integer of v (in units of 1/kScale).
int64_t Fixed(double v) { return static_cast<int64_t>(std::llround(v * kScale)); }

// v to 6 significant digits, as the page needs them (finite; NaN/inf become 0): keeps the
// page small.
double Short(double v) {
  if (!std::isfinite(v)) return 0;
  return std::strtod(absl::StrFormat("%.6g", v).c_str(), nullptr);
}

template <typename T, typename F>
nlohmann::json Array(const std::vector<T>& items, F format) {
  nlohmann::json out = nlohmann::json::array();
  for (const T& item : items) out.push_back(format(item));
  return out;
}

absl::StatusOr<std::string> ReadWhole(const std::string& path) {
  absl::StatusOr<std::string> bytes = ReadFile(path);
  if (!bytes.ok()) {
    return absl::Status(bytes.status().code(),
                        absl::StrCat(bytes.status().message(),
                                     " (the replay page embeds three.js: apt-get install libjs-three)"));
  }
  return bytes;
}

}  // namespace

ReplayScene BuildReplayScene(const mjModel* m) {
  ReplayScene r;
  // Bodies with drawable geoms get transforms; world geoms are static.
  std::vector<int> body_index(m->nbody, -1);
  for (int g = 0; g < m->ngeom; ++g) {
    const char* type = GeomTypeName(m->geom_type[g]);
    const int mat = m->geom_matid[g];
    const float* rgba = mat >= 0 ? m->mat_rgba + 4 * mat : m->geom_rgba + 4 * g;
    if (type == nullptr || m->geom_rgba[4 * g + 3] == 0 || rgba[3] == 0) {
      ++r.skipped_geoms;
      continue;
    }
    const int b = m->geom_bodyid[g];
    if (b > 0 && body_index[b] < 0) {
      body_index[b] = static_cast<int>(r.body_ids.size());
      r.body_ids.push_back(b);
      r.body_names.push_back(Name(m, mjOBJ_BODY, b));
    }
    ReplayGeom geom;
    geom.name = Name(m, mjOBJ_GEOM, g);
    geom.body = b > 0 ? body_index[b] : -1;
    geom.type = type;
    for (int k = 0; k < 3; ++k) geom.size[k] = m->geom_size[3 * g + k];
    for (int k = 0; k < 3; ++k) geom.pos[k] = m->geom_pos[3 * g + k];
    for (int k = 0; k < 4; ++k) geom.quat[k] = m->geom_quat[4 * g + k];
    for (int k = 0; k < 4; ++k) geom.rgba[k] = rgba[k];
    if (m->geom_type[g] == mjGEOM_MESH) {
      const int mesh = m->geom_dataid[g];
      const float* vert = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
      const int* face = m->mesh_face + 3 * m->mesh_faceadr[mesh];
      geom.vertices.assign(vert, vert + 3 * m->mesh_vertnum[mesh]);
      geom.faces.assign(face, face + 3 * m->mesh_facenum[mesh]);
    }
    r.geoms.push_back(geom);
  }
  // The follow camera tracks the character's root: the first drawn body outside the balls.
  for (size_t i = 0; i < r.body_ids.size(); ++i) {
    if (!InBallSubtree(m, r.body_ids[i])) {
      const int root = m->body_rootid[r.body_ids[i]];
      r.follow = body_index[root] >= 0 ? body_index[root] : static_cast<int>(i);
      break;
    }
  }

  return r;
}

absl::StatusOr<ReplayData> BuildReplayData(const mjModel* m, const Trajectory& t, int episode) {
  if (t.num_samples() == 0) return absl::InvalidArgumentError("the recording has no samples");
  if (t.nq != m->nq) {
    return absl::InvalidArgumentError(
        absl::StrCat("the recording has nq ", t.nq, " but the model ", m->nq));
  }
  ReplayData r;
  r.family = t.family;
  r.config_path = t.config_path;
  r.control_dt = t.control_dt;
  r.channels = t.channels;
  for (int i = 0; i < t.num_samples(); ++i) {
    if (episode < 0 || t.episode(i) == episode) r.samples.push_back(i);
  }
  if (r.samples.empty()) {
    return absl::InvalidArgumentError(absl::StrCat("the recording has no episode ", episode,
                                                   " (episodes 0..", t.episode(t.num_samples() - 1),
                                                   ")"));
  }

  ReplayScene scene = BuildReplayScene(m);
  r.body_ids = std::move(scene.body_ids);
  r.body_names = std::move(scene.body_names);
  r.follow = scene.follow;
  r.geoms = std::move(scene.geoms);
  r.skipped_geoms = scene.skipped_geoms;

  MjDataPtr d(mj_makeData(m));
  const int nb = static_cast<int>(r.body_ids.size());
  const int nc = t.num_channels();
  const double t0 = t.time[r.samples.front()];
  r.xpos.reserve(r.samples.size() * nb * 3);
  r.xquat.reserve(r.samples.size() * nb * 4);
  for (size_t f = 0; f < r.samples.size(); ++f) {
    const int s = r.samples[f];
    r.time.push_back(t.time[s] - t0);
    for (int c = 0; c < nc; ++c) r.values.push_back(t.value(s, c));
    mju_copy(d->qpos, t.qpos_at(s), m->nq);
    mju_zero(d->qvel, m->nv);
    mj_forward(m, d.get());
    for (int b : r.body_ids) {
      r.xpos.insert(r.xpos.end(), d->xpos + 3 * b, d->xpos + 3 * b + 3);
      r.xquat.insert(r.xquat.end(), d->xquat + 4 * b, d->xquat + 4 * b + 4);
    }
    // Ball contacts, one per (ball, other) pair.
    std::set<std::pair<std::string, std::string>> seen;
    for (int c = 0; c < d->ncon; ++c) {
      const mjContact& con = d->contact[c];
      int g1 = con.geom1, g2 = con.geom2;
      if (!InBallSubtree(m, m->geom_bodyid[g1])) std::swap(g1, g2);
      const int ball = m->geom_bodyid[g1], other = m->geom_bodyid[g2];
      if (!InBallSubtree(m, ball) || InBallSubtree(m, other)) continue;
      std::pair<std::string, std::string> key(
          Name(m, mjOBJ_BODY, m->body_rootid[ball]),
          other == 0 ? Name(m, mjOBJ_GEOM, g2) : Name(m, mjOBJ_BODY, other));
      if (key.second.empty()) key.second = other == 0 ? "world" : absl::StrCat("body", other);
      if (seen.insert(key).second) {
        r.contacts.push_back({static_cast<int>(f), key.first, key.second});
      }
    }
    // Episode starts and categorical channel changes.
    const bool new_episode = f == 0 || t.episode(s) != t.episode(r.samples[f - 1]);
    if (new_episode) {
      r.events.push_back({static_cast<int>(f), "episode", absl::StrCat(t.episode(s))});
    }
    for (int c = 0; c < nc; ++c) {
      if (t.channels[c].labels.empty()) continue;
      if (new_episode ? c != kOutcomeChannel
                      : t.value(s, c) != t.value(r.samples[f - 1], c)) {
        r.events.push_back({static_cast<int>(f), t.channels[c].name, t.Label(s, c)});
      }
    }
  }
  return r;
}

namespace {

nlohmann::ordered_json GeomsJson(const std::vector<ReplayGeom>& geoms) {
  using Json = nlohmann::ordered_json;
  auto shorts = [](const auto& v) {
    Json a = Json::array();
    for (double x : v) a.push_back(Short(x));
    return a;
  };
  Json out = Json::array();
  for (const ReplayGeom& g : geoms) {
    Json geom = {{"name", g.name}, {"body", g.body}, {"type", g.type},
                 {"size", shorts(g.size)}, {"pos", shorts(g.pos)},
                 {"quat", shorts(g.quat)}, {"rgba", shorts(g.rgba)}};
    if (!g.vertices.empty()) {
      geom["vertices"] = shorts(g.vertices);
      geom["faces"] = g.faces;
    }
    out.push_back(std::move(geom));
  }
  return out;
}

}  // namespace

std::string ReplayGeomsJson(const std::vector<ReplayGeom>& geoms) {
  return GeomsJson(geoms).dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string ReplayJson(const ReplayData& r) {
  using Json = nlohmann::ordered_json;
  auto shorts = [](const auto& v) {
    Json a = Json::array();
    for (double x : v) a.push_back(Short(x));
    return a;
  };
  auto fixed = [](double v) { return Fixed(v); };
  Json geoms = GeomsJson(r.geoms), channels = Json::array(), contacts = Json::array(),
       events = Json::array();
  for (const AnnotationChannel& c : r.channels) {
    channels.push_back({{"name", c.name}, {"labels", c.labels}});
  }
  for (const ReplayContact& c : r.contacts) contacts.push_back({c.frame, c.ball, c.other});
  for (const ReplayEvent& e : r.events) events.push_back({e.frame, e.channel, e.label});
  const Json j = {
      {"version", 1},
      {"scale", static_cast<int>(kScale)},
      {"family", r.family},
      {"config", r.config_path},
      {"control_dt", Short(r.control_dt)},
      {"follow", r.follow},
      {"bodies", r.body_names},
      {"geoms", std::move(geoms)},
      {"channels", std::move(channels)},
      {"time", Array(r.time, fixed)},
      {"values", shorts(r.values)},
      {"xpos", Array(r.xpos, fixed)},
      {"xquat", Array(r.xquat, fixed)},
      {"contacts", std::move(contacts)},
      {"events", std::move(events)},
  };
  // '<' escaped: no "</script" can appear in the page the JSON is embedded in.
  return absl::StrReplaceAll(j.dump(-1, ' ', false, Json::error_handler_t::replace),
                             {{"<", "\\u003c"}});
}

absl::StatusOr<ReplayLibraries> LoadReplayLibraries(const std::string& dir) {
  ReplayLibraries libs;
  absl::StatusOr<std::string> three = ReadWhole(dir + "/three.min.js");
  if (!three.ok()) return three.status();
  absl::StatusOr<std::string> orbit = ReadWhole(dir + "/examples/js/controls/OrbitControls.js");
  if (!orbit.ok()) return orbit.status();
  libs.three_js = *std::move(three);
  libs.orbit_controls_js = *std::move(orbit);
  return libs;
}

std::string ReplayHtml(const ReplayData& data, const ReplayLibraries& libraries,
                       const std::string& title) {
  // A script's text must not close its element early.
  auto script = [](const std::string& attributes, const std::string& text) {
    return absl::StrCat("<script", attributes, ">\n",
                        absl::StrReplaceAll(text, {{"</script", "<\\/script"}}), "\n</script>\n");
  };
  const std::string scripts =
      absl::StrCat(script("", libraries.three_js), script("", libraries.orbit_controls_js),
                   script(" id=\"replay-data\" type=\"application/json\"", ReplayJson(data)),
                   script("", kSceneJs), script("", kReplayJs));
  std::string escaped_title = absl::StrReplaceAll(title, {{"&", "&amp;"}, {"<", "&lt;"}});
  return absl::StrReplaceAll(kReplayHtml, {{"<!-- juggle:title -->", escaped_title},
                                           {"<!-- juggle:scripts -->", scripts}});
}

}  // namespace juggle
