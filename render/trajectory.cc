#include "render/trajectory.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "render/image.h"

namespace juggle {
namespace {

// float64 <-> 8 little-endian bytes, whatever the host byte order.
void PutDouble(double v, std::string* out) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  char b[8];
  for (int i = 0; i < 8; ++i) b[i] = static_cast<char>(bits >> (8 * i));
  out->append(b, 8);
}

double GetDouble(const char* p) {
  uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= static_cast<uint64_t>(static_cast<uint8_t>(p[i])) << (8 * i);
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

absl::Status Invalid(const std::string& path, const std::string& why) {
  return absl::InvalidArgumentError(absl::StrCat(path, ": not a juggle trajectory (v",
                                                 kTrajectoryVersion, "): ", why));
}

// Full model qpos of a sample: the character's 43, the ball's 7, the model's qpos0 elsewhere.
void SampleQpos(const JuggleSpec& spec, const TrajectorySample& s, double* qpos) {
  const mjModel* m = spec.model();
  mju_copy(qpos, m->qpos0, m->nq);
  mju_copy(qpos, s.qpos.data(), kCharacterNq);
  mju_copy(qpos + spec.ball_qpos(), s.ball_pos.data(), 3);
  mju_copy(qpos + spec.ball_qpos() + 3, s.ball_quat.data(), 4);
}

// q = slerp(a, b, alpha), via the rotation vector from a to b.
void Slerp(const double* a, const double* b, double alpha, double* q) {
  double rel[3];
  mju_subQuat(rel, b, a);  // a * quat(rel) = b
  mju_copy4(q, a);
  mju_quatIntegrate(q, rel, alpha);
}

}  // namespace

absl::Status WriteTrajectory(const Trajectory& t, const std::string& path) {
  for (const std::string& name : t.node_names) {
    if (name.empty() || name.find_first_of(", \n\t") != std::string::npos) {
      return absl::InvalidArgumentError(
          absl::StrCat("node name '", name, "' cannot be recorded (empty, comma or space)"));
    }
  }
  if (t.config_path.find('\n') != std::string::npos) {
    return absl::InvalidArgumentError("config path with a newline cannot be recorded");
  }
  std::string out = absl::StrCat(kTrajectoryMagic, " ", kTrajectoryVersion,
                                 " record_doubles=", kTrajectoryRecordDoubles,
                                 " nq=", kCharacterNq, " control_dt=", t.control_dt,
                                 " nodes=", absl::StrJoin(t.node_names, ","),
                                 " config=", t.config_path, "\n");
  out.reserve(out.size() + t.samples.size() * kTrajectoryRecordDoubles * 8);
  for (const TrajectorySample& s : t.samples) {
    PutDouble(s.time, &out);
    PutDouble(s.episode, &out);
    PutDouble(s.episode_time, &out);
    PutDouble(s.node, &out);
    PutDouble(s.phase, &out);
    PutDouble(static_cast<double>(s.outcome), &out);
    for (double v : s.qpos) PutDouble(v, &out);
    for (double v : s.ball_pos) PutDouble(v, &out);
    for (double v : s.ball_quat) PutDouble(v, &out);
  }
  return WriteFileBytes(path, out);
}

absl::StatusOr<Trajectory> ReadTrajectory(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return absl::NotFoundError(absl::StrCat("cannot open trajectory ", path, ": ",
                                            std::strerror(errno)));
  }
  std::string header;
  if (!std::getline(in, header)) return Invalid(path, "empty file");
  if (header.rfind(absl::StrCat(kTrajectoryMagic, " "), 0) != 0) return Invalid(path, "bad magic");
  Trajectory t;
  // config= is last and runs to the end of the line (paths may hold spaces).
  const size_t config_at = header.find(" config=");
  if (config_at == std::string::npos) return Invalid(path, "header has no config=");
  t.config_path = header.substr(config_at + 8);
  const std::vector<std::string> fields =
      absl::StrSplit(header.substr(0, config_at), ' ', absl::SkipEmpty());
  if (fields.size() < 2 || fields[0] != kTrajectoryMagic) return Invalid(path, "bad magic");
  if (fields[1] != std::to_string(kTrajectoryVersion)) {
    return Invalid(path, absl::StrCat("version ", fields[1]));
  }
  bool have_nodes = false, have_dt = false;
  for (size_t i = 2; i < fields.size(); ++i) {
    const size_t eq = fields[i].find('=');
    if (eq == std::string::npos) return Invalid(path, absl::StrCat("bad field ", fields[i]));
    const std::string key = fields[i].substr(0, eq), value = fields[i].substr(eq + 1);
    if (key == "record_doubles" && value != std::to_string(kTrajectoryRecordDoubles)) {
      return Invalid(path, absl::StrCat("record_doubles=", value, ", expected ",
                                        kTrajectoryRecordDoubles));
    }
    if (key == "nq" && value != std::to_string(kCharacterNq)) {
      return Invalid(path, absl::StrCat("nq=", value, ", expected ", kCharacterNq));
    }
    if (key == "control_dt") {
      if (!absl::SimpleAtod(value, &t.control_dt) || !(t.control_dt > 0)) {
        return Invalid(path, absl::StrCat("control_dt=", value));
      }
      have_dt = true;
    }
    if (key == "nodes") {
      t.node_names = absl::StrSplit(value, ',', absl::SkipEmpty());
      have_nodes = !t.node_names.empty();
    }
  }
  if (!have_nodes || !have_dt) return Invalid(path, "header lacks nodes= or control_dt=");

  std::stringstream body;
  body << in.rdbuf();
  const std::string bytes = body.str();
  constexpr size_t kRecordBytes = kTrajectoryRecordDoubles * 8;
  if (bytes.size() % kRecordBytes != 0) {
    return Invalid(path, absl::StrCat("truncated: ", bytes.size(), " bytes of records is not a ",
                                      "multiple of ", kRecordBytes));
  }
  const size_t n = bytes.size() / kRecordBytes;
  t.samples.resize(n);
  for (size_t r = 0; r < n; ++r) {
    const char* p = bytes.data() + r * kRecordBytes;
    auto next = [&p] {
      const double v = GetDouble(p);
      p += 8;
      return v;
    };
    TrajectorySample& s = t.samples[r];
    s.time = next();
    s.episode = static_cast<int>(next());
    s.episode_time = next();
    s.node = static_cast<int>(next());
    s.phase = next();
    const double outcome = next();
    for (double& v : s.qpos) v = next();
    for (double& v : s.ball_pos) v = next();
    for (double& v : s.ball_quat) v = next();
    if (s.node < 0 || s.node >= static_cast<int>(t.node_names.size())) {
      return Invalid(path, absl::StrCat("record ", r, ": node ", s.node, " out of range"));
    }
    if (!(outcome >= 0 && outcome < static_cast<double>(Outcome::kNumOutcomes))) {
      return Invalid(path, absl::StrCat("record ", r, ": outcome ", outcome, " out of range"));
    }
    s.outcome = static_cast<Outcome>(static_cast<int>(outcome));
    if (r > 0 && s.time < t.samples[r - 1].time) {
      return Invalid(path, absl::StrCat("record ", r, ": time goes backwards"));
    }
  }
  return t;
}

TrajectorySample CaptureSample(const JuggleEnv& env) {
  const JuggleSpec& spec = env.spec();
  const mjData* d = env.data();
  TrajectorySample s;
  s.episode_time = env.steps() * spec.control_dt();
  s.node = env.cursor().current;
  s.phase = env.cursor().phase;
  std::copy(d->qpos, d->qpos + kCharacterNq, s.qpos.begin());
  const double* ball = d->qpos + spec.ball_qpos();
  std::copy(ball, ball + 3, s.ball_pos.begin());
  std::copy(ball + 3, ball + 7, s.ball_quat.begin());
  return s;
}

double Duration(const Trajectory& trajectory) {
  return trajectory.samples.empty() ? 0 : trajectory.samples.back().time;
}

FrameInfo PoseAt(const JuggleSpec& spec, const Trajectory& trajectory, double time,
                 mjData* data) {
  const mjModel* m = spec.model();
  const std::vector<TrajectorySample>& samples = trajectory.samples;
  // Last sample at or before `time` (a reset sample wins over the episode end it shares a
  // time with).
  auto it = std::upper_bound(samples.begin(), samples.end(), time,
                             [](double t, const TrajectorySample& s) { return t < s.time; });
  const int i = std::max(0, static_cast<int>(it - samples.begin()) - 1);
  const TrajectorySample& a = samples[i];
  FrameInfo info;
  info.sample = i;
  info.episode = a.episode;
  info.episode_time = a.episode_time;
  info.node = a.node;
  info.phase = a.phase;
  info.outcome = a.outcome;

  SampleQpos(spec, a, data->qpos);
  const bool has_next = i + 1 < static_cast<int>(samples.size()) &&
                        samples[i + 1].episode == a.episode && samples[i + 1].time > a.time;
  const double alpha = has_next ? (time - a.time) / (samples[i + 1].time - a.time) : 0.0;
  if (alpha > 0) {
    const double w = std::min(alpha, 1.0);
    const TrajectorySample& b = samples[i + 1];
    info.episode_time = a.episode_time + w * (b.episode_time - a.episode_time);
    std::vector<double> qb(m->nq);
    SampleQpos(spec, b, qb.data());
    double* q = data->qpos;
    for (int j = 0; j < m->njnt; ++j) {
      const int adr = m->jnt_qposadr[j];
      int linear = 0;
      switch (m->jnt_type[j]) {
        case mjJNT_FREE:
          for (int k = 0; k < 3; ++k) q[adr + k] += w * (qb[adr + k] - q[adr + k]);
          Slerp(q + adr + 3, qb.data() + adr + 3, w, q + adr + 3);
          break;
        case mjJNT_BALL:
          Slerp(q + adr, qb.data() + adr, w, q + adr);
          break;
        default:
          linear = 1;
          break;
      }
      if (linear) q[adr] += w * (qb[adr] - q[adr]);
    }
  }
  mju_zero(data->qvel, m->nv);
  mj_forward(m, data);
  return info;
}

}  // namespace juggle
