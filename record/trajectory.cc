#include "record/trajectory.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "common/file_io.h"

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

// q = slerp(a, b, alpha), via the rotation vector from a to b.
void Slerp(const double* a, const double* b, double alpha, double* q) {
  double rel[3];
  mju_subQuat(rel, b, a);  // a * quat(rel) = b
  mju_copy4(q, a);
  mju_quatIntegrate(q, rel, alpha);
}

// Splits "key rest of line" at the first space.
std::pair<std::string, std::string> KeyValue(const std::string& line) {
  const size_t space = line.find(' ');
  if (space == std::string::npos) return {line, ""};
  return {line.substr(0, space), line.substr(space + 1)};
}

}  // namespace

int Trajectory::FindChannel(const std::string& name) const {
  for (int c = 0; c < num_channels(); ++c) {
    if (channels[c].name == name) return c;
  }
  return -1;
}

std::string Trajectory::Label(int sample, int channel) const {
  const std::vector<std::string>& labels = channels[channel].labels;
  const int v = static_cast<int>(value(sample, channel));
  return v >= 0 && v < static_cast<int>(labels.size()) ? labels[v] : "";
}

int Trajectory::EpisodeEnd(int e) const {
  for (int i = num_samples() - 1; i >= 0; --i) {
    if (episode(i) == e) return i;
  }
  return -1;
}

TrajectoryBuilder::TrajectoryBuilder(std::string family, std::string config_path,
                                     double control_dt, int nq,
                                     std::vector<std::string> outcome_names,
                                     std::vector<AnnotationChannel> family_channels) {
  t_.family = std::move(family);
  t_.config_path = std::move(config_path);
  t_.control_dt = control_dt;
  t_.nq = nq;
  t_.channels = {{"episode", {}}, {"episode_time", {}}, {"outcome", std::move(outcome_names)}};
  for (AnnotationChannel& c : family_channels) t_.channels.push_back(std::move(c));
}

void TrajectoryBuilder::Append(double time, int episode, double episode_time, Outcome outcome,
                               const double* annotations, const double* qpos) {
  t_.time.push_back(time);
  t_.values.push_back(episode);
  t_.values.push_back(episode_time);
  t_.values.push_back(static_cast<double>(outcome));
  t_.values.insert(t_.values.end(), annotations, annotations + (t_.channels.size() - 3));
  t_.qpos.insert(t_.qpos.end(), qpos, qpos + t_.nq);
}

void AppendEpisode(const Trajectory& from, int episode, int new_episode, Trajectory* into) {
  const double offset = into->duration();
  double first_time = -1;
  for (int i = 0; i < from.num_samples(); ++i) {
    if (from.episode(i) != episode) continue;
    if (first_time < 0) first_time = from.time[i];
    into->time.push_back(offset + from.time[i] - first_time);
    const size_t v0 = into->values.size();
    into->values.insert(into->values.end(), from.values.begin() + size_t(i) * from.num_channels(),
                        from.values.begin() + size_t(i + 1) * from.num_channels());
    into->values[v0 + kEpisodeChannel] = new_episode;
    into->qpos.insert(into->qpos.end(), from.qpos_at(i), from.qpos_at(i) + from.nq);
  }
}

absl::Status WriteTrajectory(const Trajectory& t, const std::string& path) {
  for (const AnnotationChannel& c : t.channels) {
    if (c.name.empty() || c.name.find_first_of(", \n\t") != std::string::npos) {
      return absl::InvalidArgumentError(absl::StrCat("channel name '", c.name,
                                                     "' cannot be recorded"));
    }
    for (const std::string& label : c.labels) {
      if (label.empty() || label.find_first_of(", \n\t") != std::string::npos) {
        return absl::InvalidArgumentError(absl::StrCat(
            "label '", label, "' of channel ", c.name, " cannot be recorded (empty, comma or space)"));
      }
    }
  }
  if (t.config_path.find('\n') != std::string::npos || t.family.find_first_of(" \n") != std::string::npos) {
    return absl::InvalidArgumentError("config path or family with a newline cannot be recorded");
  }
  std::string out = absl::StrCat(kTrajectoryMagic, " ", kTrajectoryVersion, "\nfamily ", t.family,
                                 "\nconfig ", t.config_path, "\ncontrol_dt ", t.control_dt,
                                 "\nnq ", t.nq, "\n");
  for (const AnnotationChannel& c : t.channels) {
    absl::StrAppend(&out, "channel ", c.name, c.labels.empty() ? "" : " ",
                    absl::StrJoin(c.labels, ","), "\n");
  }
  absl::StrAppend(&out, "data ", t.num_samples(), "\n");
  out.reserve(out.size() + t.time.size() * (1 + t.channels.size() + t.nq) * 8);
  for (int i = 0; i < t.num_samples(); ++i) {
    PutDouble(t.time[i], &out);
    for (int c = 0; c < t.num_channels(); ++c) PutDouble(t.value(i, c), &out);
    for (int q = 0; q < t.nq; ++q) PutDouble(t.qpos_at(i)[q], &out);
  }
  return WriteFile(path, out);
}

absl::StatusOr<Trajectory> ReadTrajectory(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return absl::NotFoundError(absl::StrCat("cannot open trajectory ", path, ": ",
                                            std::strerror(errno)));
  }
  std::string line;
  if (!std::getline(in, line)) return Invalid(path, "empty file");
  const auto [magic, version] = KeyValue(line);
  if (magic != kTrajectoryMagic) return Invalid(path, "bad magic");
  if (version != std::to_string(kTrajectoryVersion)) {
    return Invalid(path, absl::StrCat("version ", version, " (this build reads version ",
                                      kTrajectoryVersion, "; re-record it)"));
  }
  Trajectory t;
  int64_t records = -1;
  while (records < 0 && std::getline(in, line)) {
    const auto [key, value] = KeyValue(line);
    if (key == "family") {
      t.family = value;
    } else if (key == "config") {
      t.config_path = value;
    } else if (key == "control_dt") {
      if (!absl::SimpleAtod(value, &t.control_dt) || !(t.control_dt > 0)) {
        return Invalid(path, absl::StrCat("control_dt ", value));
      }
    } else if (key == "nq") {
      if (!absl::SimpleAtoi(value, &t.nq) || t.nq < 1 || t.nq > 100000) {
        return Invalid(path, absl::StrCat("nq ", value));
      }
    } else if (key == "channel") {
      const auto [name, labels] = KeyValue(value);
      AnnotationChannel c{name, {}};
      if (!labels.empty()) c.labels = absl::StrSplit(labels, ',');
      t.channels.push_back(std::move(c));
    } else if (key == "data") {
      if (!absl::SimpleAtoi(value, &records) || records < 0) {
        return Invalid(path, absl::StrCat("data ", value));
      }
    } else {
      return Invalid(path, absl::StrCat("unknown header line '", line, "'"));
    }
  }
  if (records < 0) return Invalid(path, "header has no data line");
  if (t.family.empty() || t.nq == 0 || t.control_dt == 0 || t.channels.size() < 3 ||
      t.channels[kEpisodeChannel].name != "episode" ||
      t.channels[kEpisodeTimeChannel].name != "episode_time" ||
      t.channels[kOutcomeChannel].name != "outcome") {
    return Invalid(path, "header lacks family, nq, control_dt or the standard channels");
  }
  std::stringstream body;
  body << in.rdbuf();
  const std::string bytes = body.str();
  const size_t doubles = 1 + t.channels.size() + t.nq;
  // Compared by division first: records × doubles × 8 may overflow for a hostile header.
  if (static_cast<uint64_t>(records) > bytes.size() / (doubles * 8) ||
      bytes.size() != static_cast<size_t>(records) * doubles * 8) {
    return Invalid(path, absl::StrCat("truncated: ", bytes.size(), " bytes of records, expected ",
                                      records, " × ", doubles * 8));
  }
  t.time.resize(records);
  t.values.resize(records * t.channels.size());
  t.qpos.resize(records * t.nq);
  const char* p = bytes.data();
  auto next = [&p] {
    const double v = GetDouble(p);
    p += 8;
    return v;
  };
  for (int64_t r = 0; r < records; ++r) {
    t.time[r] = next();
    for (size_t c = 0; c < t.channels.size(); ++c) {
      const double v = next();
      const std::vector<std::string>& labels = t.channels[c].labels;
      if (!labels.empty() && !(v >= 0 && v < static_cast<double>(labels.size()))) {
        return Invalid(path, absl::StrCat("record ", r, ": ", t.channels[c].name, " ", v,
                                          " outside its ", labels.size(), " labels"));
      }
      t.values[r * t.channels.size() + c] = v;
    }
    for (int q = 0; q < t.nq; ++q) t.qpos[r * t.nq + q] = next();
    if (r > 0 && t.time[r] < t.time[r - 1]) {
      return Invalid(path, absl::StrCat("record ", r, ": time goes backwards"));
    }
  }
  return t;
}

FrameInfo PoseAt(const mjModel* m, const Trajectory& t, double time, mjData* data) {
  // Last sample at or before `time` (a reset sample wins over the episode end it shares a
  // time with).
  auto it = std::upper_bound(t.time.begin(), t.time.end(), time);
  const int i = std::max(0, static_cast<int>(it - t.time.begin()) - 1);
  FrameInfo info;
  info.sample = i;
  info.episode = t.episode(i);
  info.episode_time = t.value(i, kEpisodeTimeChannel);
  mju_copy(data->qpos, t.qpos_at(i), m->nq);
  const bool has_next =
      i + 1 < t.num_samples() && t.episode(i + 1) == info.episode && t.time[i + 1] > t.time[i];
  const double alpha = has_next ? (time - t.time[i]) / (t.time[i + 1] - t.time[i]) : 0.0;
  if (alpha > 0) {
    const double w = std::min(alpha, 1.0);
    info.episode_time += w * (t.value(i + 1, kEpisodeTimeChannel) - info.episode_time);
    const double* qb = t.qpos_at(i + 1);
    double* q = data->qpos;
    for (int j = 0; j < m->njnt; ++j) {
      const int adr = m->jnt_qposadr[j];
      switch (m->jnt_type[j]) {
        case mjJNT_FREE:
          for (int k = 0; k < 3; ++k) q[adr + k] += w * (qb[adr + k] - q[adr + k]);
          Slerp(q + adr + 3, qb + adr + 3, w, q + adr + 3);
          break;
        case mjJNT_BALL:
          Slerp(q + adr, qb + adr, w, q + adr);
          break;
        default:
          q[adr] += w * (qb[adr] - q[adr]);
          break;
      }
    }
  }
  mju_zero(data->qvel, m->nv);
  mj_forward(m, data);
  return info;
}

}  // namespace juggle
