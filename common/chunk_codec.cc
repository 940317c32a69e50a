#include "common/chunk_codec.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/outcome.h"
#include "common/status_macros.h"

namespace juggle {

namespace {

template <typename T, typename Field>
void CopyRange(const std::vector<T>& src, size_t begin, size_t end, Field* dst) {
  dst->Reserve(static_cast<int>(end - begin));
  for (size_t i = begin; i < end; ++i) dst->Add(src[i]);
}

}  // namespace

std::vector<rpc::TrajectoryChunk> EncodeContribution(const Contribution& c, uint64_t incarnation,
                                                     int64_t sequence, size_t max_bytes) {
  const UnrollBatch& b = c.batch;
  const int U = b.num_unrolls, T = b.unroll_length, D = b.obs_dim, A = b.act_dim;
  const size_t per_unroll = size_t(T) * (D + A * (b.has_labels() ? 2 : 1) + 4) * 4 + size_t(D) * 4;
  const int per_chunk = std::max<int>(1, static_cast<int>(max_bytes / std::max<size_t>(per_unroll, 1)));
  const int parts = (U + per_chunk - 1) / per_chunk;
  std::vector<rpc::TrajectoryChunk> chunks(parts);
  // Index of the first truncated observation of each unroll.
  std::vector<size_t> trunc_start(U + 1, 0);
  // And of the first label row.
  std::vector<size_t> label_start(U + 1, 0);
  for (int u = 0; u < U; ++u) {
    int n = 0;
    for (int t = 0; t < T; ++t) n += b.truncated[size_t(u) * T + t];
    trunc_start[u + 1] = trunc_start[u] + n;
    label_start[u + 1] = label_start[u] + (b.has_labels() && b.labelled[u] ? 1 : 0);
  }
  for (int p = 0; p < parts; ++p) {
    rpc::TrajectoryChunk& ch = chunks[p];
    const int u0 = p * per_chunk, u1 = std::min(U, u0 + per_chunk);
    ch.set_incarnation(incarnation);
    ch.set_policy_version(b.policy_version.empty() ? 0 : b.policy_version[0]);
    ch.set_sequence(sequence);
    ch.set_part(p);
    ch.set_num_parts(parts);
    ch.set_num_unrolls(u1 - u0);
    ch.set_unroll_length(T);
    ch.set_obs_dim(D);
    ch.set_act_dim(A);
    const size_t s0 = size_t(u0) * T, s1 = size_t(u1) * T;
    CopyRange(b.obs, s0 * D, s1 * D, ch.mutable_obs());
    CopyRange(b.actions, s0 * A, s1 * A, ch.mutable_actions());
    CopyRange(b.log_probs, s0, s1, ch.mutable_log_probs());
    CopyRange(b.rewards, s0, s1, ch.mutable_rewards());
    ch.set_done(std::string(b.done.begin() + s0, b.done.begin() + s1));
    ch.set_truncated(std::string(b.truncated.begin() + s0, b.truncated.begin() + s1));
    CopyRange(b.truncated_obs, trunc_start[u0] * D, trunc_start[u1] * D, ch.mutable_truncated_obs());
    CopyRange(b.bootstrap_obs, size_t(u0) * D, size_t(u1) * D, ch.mutable_bootstrap_obs());
    CopyRange(c.node, s0, s1, ch.mutable_node());
    if (b.has_labels()) {
      ch.set_labelled(std::string(b.labelled.begin() + u0, b.labelled.begin() + u1));
      const size_t row = size_t(T) * A;
      CopyRange(b.labels, label_start[u0] * row, label_start[u1] * row, ch.mutable_labels());
      if (!b.expert_driven.empty()) {
        ch.set_expert_driven(std::string(b.expert_driven.begin() + u0, b.expert_driven.begin() + u1));
      }
    }
  }
  // Events and episode statistics travel with the last part.
  rpc::TrajectoryChunk& last = chunks.back();
  for (const EdgeEvent& e : c.events) {
    last.mutable_edge_events()->add_edge(e.edge);
    last.mutable_edge_events()->add_type(static_cast<int>(e.type));
  }
  last.set_episodes(c.stats.episodes);
  last.set_episode_return_sum(c.stats.return_sum);
  last.set_episode_length_sum(c.stats.length_sum);
  last.set_completions_sum(c.stats.completions_sum);
  last.set_juggles_sum(c.stats.juggles_sum);
  for (int64_t o : c.stats.outcomes) last.add_outcomes(o);
  last.set_expert_episodes(c.expert_stats.episodes);
  last.set_expert_juggles_sum(c.expert_stats.juggles_sum);
  last.set_expert_length_sum(c.expert_stats.length_sum);
  if (c.expert_cost.labels > 0 || c.expert_cost.replans > 0) {
    rpc::ExpertCost* cost = last.mutable_expert_cost();
    cost->set_labels(c.expert_cost.labels);
    cost->set_replans(c.expert_cost.replans);
    cost->set_rollout_steps(c.expert_cost.rollout_steps);
    cost->set_rescues(c.expert_cost.rescues);
    cost->set_proposal_tried(c.expert_cost.proposal_tried);
    cost->set_proposal_chosen(c.expert_cost.proposal_chosen);
    cost->set_proposal_weight_sum(c.expert_cost.proposal_weight_sum);
  }
  return chunks;
}

absl::StatusOr<Contribution> DecodeChunk(const rpc::TrajectoryChunk& ch, int obs_dim, int act_dim,
                                         int num_nodes, int num_edges) {
  auto invalid = [](const std::string& what) { return absl::InvalidArgumentError(what); };
  if (ch.num_parts() < 1 || ch.part() < 0 || ch.part() >= ch.num_parts()) {
    return invalid(absl::StrCat("chunk part ", ch.part(), " of ", ch.num_parts(), " is invalid"));
  }
  // Claimed sizes are checked against what the message carries before anything is allocated
  // from them (the message itself is bounded by gRPC's receive limit).
  const int64_t claimed = int64_t{ch.num_unrolls()} * ch.unroll_length();
  if (ch.num_unrolls() < 1 || ch.unroll_length() < 1 || claimed != ch.rewards_size()) {
    return invalid(absl::StrCat("chunk claims ", ch.num_unrolls(), " unrolls of ",
                                ch.unroll_length(), " steps but carries ", ch.rewards_size(),
                                " rewards"));
  }
  Contribution c;
  UnrollBatch& b = c.batch;
  b.num_unrolls = ch.num_unrolls();
  b.unroll_length = ch.unroll_length();
  b.obs_dim = ch.obs_dim();
  b.act_dim = ch.act_dim();
  b.obs.assign(ch.obs().begin(), ch.obs().end());
  b.actions.assign(ch.actions().begin(), ch.actions().end());
  b.log_probs.assign(ch.log_probs().begin(), ch.log_probs().end());
  b.rewards.assign(ch.rewards().begin(), ch.rewards().end());
  b.done.assign(ch.done().begin(), ch.done().end());
  b.truncated.assign(ch.truncated().begin(), ch.truncated().end());
  b.truncated_obs.assign(ch.truncated_obs().begin(), ch.truncated_obs().end());
  b.bootstrap_obs.assign(ch.bootstrap_obs().begin(), ch.bootstrap_obs().end());
  b.policy_version.assign(std::max(0, b.num_unrolls), ch.policy_version());
  // Label sizes against the masks before the labels are copied.
  if (!ch.labelled().empty() && int64_t(ch.labelled().size()) == b.num_unrolls) {
    int64_t rows = 0;
    for (char l : ch.labelled()) rows += l == 1;
    if (rows * b.unroll_length * b.act_dim != ch.labels_size()) {
      return invalid(absl::StrCat("chunk field 'labels' has ", ch.labels_size(),
                                  " entries, expected ", rows * b.unroll_length * b.act_dim,
                                  " (", rows, " labelled unrolls)"));
    }
  }
  b.labelled.assign(ch.labelled().begin(), ch.labelled().end());
  b.labels.assign(ch.labels().begin(), ch.labels().end());
  b.expert_driven.assign(ch.expert_driven().begin(), ch.expert_driven().end());
  // Shapes, flags and finiteness; the version is checked by the learner against its own.
  RETURN_IF_ERROR(ValidateUnrollBatch(b, obs_dim, act_dim, ch.policy_version(), 0));
  if (ch.node_size() != b.num_samples()) {
    return invalid(absl::StrCat("chunk field 'node' has ", ch.node_size(), " entries, expected ",
                                b.num_samples()));
  }
  for (int i = 0; i < ch.node_size(); ++i) {
    if (ch.node(i) < 0 || ch.node(i) >= num_nodes) {
      return invalid(absl::StrCat("chunk has unknown node id ", ch.node(i), " at step ", i,
                                  " (the graph has ", num_nodes, " nodes)"));
    }
  }
  c.node.assign(ch.node().begin(), ch.node().end());
  const rpc::EdgeEvents& ev = ch.edge_events();
  if (ev.edge_size() != ev.type_size()) return invalid("edge_events: edge and type sizes differ");
  for (int i = 0; i < ev.edge_size(); ++i) {
    if (ev.edge(i) < 0 || ev.edge(i) >= num_edges) {
      return invalid(absl::StrCat("edge event ", i, " (edge ", ev.edge(i), ", type ", ev.type(i),
                                  ") is outside the graph's ", num_edges, " edges"));
    }
    if (ev.type(i) < 0 || ev.type(i) > 2) {
      return invalid(absl::StrCat("edge event ", i, " (edge ", ev.edge(i), ", type ", ev.type(i),
                                  ") has an unknown type (expected 0, 1 or 2)"));
    }
    c.events.push_back({ev.edge(i), static_cast<EdgeEventType>(ev.type(i))});
  }
  bool negative = ch.episodes() < 0 || ch.episode_length_sum() < 0 || ch.completions_sum() < 0 ||
                  ch.juggles_sum() < 0 || ch.outcomes_size() > kMaxOutcomes ||
                  ch.expert_episodes() < 0 || ch.expert_juggles_sum() < 0 ||
                  ch.expert_length_sum() < 0;
  for (int64_t o : ch.outcomes()) negative |= o < 0;
  if (!std::isfinite(ch.episode_return_sum()) || negative) {
    return invalid("chunk episode statistics are invalid");
  }
  c.stats.episodes = ch.episodes();
  c.stats.return_sum = ch.episode_return_sum();
  c.stats.length_sum = ch.episode_length_sum();
  c.stats.completions_sum = ch.completions_sum();
  c.stats.juggles_sum = ch.juggles_sum();
  c.stats.outcomes.assign(ch.outcomes().begin(), ch.outcomes().end());
  c.expert_stats.episodes = ch.expert_episodes();
  c.expert_stats.juggles_sum = ch.expert_juggles_sum();
  c.expert_stats.length_sum = ch.expert_length_sum();
  const rpc::ExpertCost& cost = ch.expert_cost();
  c.expert_cost = {cost.labels(), cost.replans(), cost.rollout_steps(), cost.rescues(),
                   cost.proposal_tried(), cost.proposal_chosen(), cost.proposal_weight_sum()};
  if (!c.expert_cost.valid()) {
    return invalid(absl::StrCat("chunk field 'expert_cost' is invalid (negative or not finite, ",
                                "or more rescues or proposal choices than re-plans): ",
                                cost.ShortDebugString()));
  }
  return c;
}

void AppendContribution(Contribution* into, const Contribution& part) {
  UnrollBatch& a = into->batch;
  const UnrollBatch& b = part.batch;
  if (a.num_unrolls == 0) {
    a.unroll_length = b.unroll_length;
    a.obs_dim = b.obs_dim;
    a.act_dim = b.act_dim;
  }
  a.num_unrolls += b.num_unrolls;
  auto append = [](auto* x, const auto& y) { x->insert(x->end(), y.begin(), y.end()); };
  append(&a.obs, b.obs);
  append(&a.actions, b.actions);
  append(&a.log_probs, b.log_probs);
  append(&a.rewards, b.rewards);
  append(&a.done, b.done);
  append(&a.truncated, b.truncated);
  append(&a.truncated_obs, b.truncated_obs);
  append(&a.bootstrap_obs, b.bootstrap_obs);
  append(&a.policy_version, b.policy_version);
  // Labels: a part without them is all unlabelled; masks are filled in when only one side has them.
  if (a.has_labels() || b.has_labels()) {
    const int before = a.num_unrolls - b.num_unrolls;
    auto mask = [](const std::vector<uint8_t>& m, int n) {
      return m.empty() ? std::vector<uint8_t>(n, 0) : m;
    };
    std::vector<uint8_t> labelled = mask(a.labelled, before), driven = mask(a.expert_driven, before);
    append(&labelled, mask(b.labelled, b.num_unrolls));
    append(&driven, mask(b.expert_driven, b.num_unrolls));
    a.labelled = std::move(labelled);
    a.expert_driven = std::move(driven);
    append(&a.labels, b.labels);
  }
  append(&into->node, part.node);
  append(&into->events, part.events);
  into->stats.Add(part.stats);
  into->expert_stats.Add(part.expert_stats);
  into->expert_cost.Add(part.expert_cost);
}

}  // namespace juggle
