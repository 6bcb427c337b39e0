#include "stripweave/elastica/loop_session.h"

#include "stripweave/core/memory_guard.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/core/error.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace stripweave {

LoopSession::LoopSession(std::shared_ptr<const Surface> surface, const ElasticaParams& params, Progress* progress)
    : surface_(std::move(surface)) {
  const auto start = std::chrono::steady_clock::now();
  // The graph is the largest allocation of weaving: refused before it is
  // built when it would not fit (core/memory_guard.h).
  const Index triangles = surface_->mesh.num_triangles();
  check_memory("the elastica graph of " + std::to_string(triangles) + " triangles (k = " + std::to_string(params.k) + ")",
               graph_memory_mb(triangles, params.k, params.max_turn_deg));
  graph_ = build_elastica_graph(*surface_, params, progress);
  locator_ = std::make_unique<SurfaceLocator>(surface_->mesh);
  tables_ = loop_tables(*surface_, graph_);
  set_threads(static_cast<int>(std::min(2u, std::max(1u, std::thread::hardware_concurrency()))));
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

LoopSession::~LoopSession() = default;

void LoopSession::set_threads(int threads) {
  ++generation_;
  std::lock_guard<std::mutex> lock(query_mutex_);
  workspaces_.resize(std::max(1, threads));
}

std::size_t LoopSession::workspace_bytes() const {
  std::lock_guard<std::mutex> lock(query_mutex_);  // after a running query
  std::size_t bytes = 0;
  for (const SearchWorkspaces& w : workspaces_) bytes += w.memory_bytes();
  return bytes;
}

void LoopSession::release_workspaces() {
  ++generation_;
  std::lock_guard<std::mutex> lock(query_mutex_);
  for (SearchWorkspaces& w : workspaces_) w.release();
}

void LoopSession::release_graph() {
  ++generation_;
  std::lock_guard<std::mutex> lock(query_mutex_);
  graph_released_ = true;
  graph_ = ElasticaGraph{};
  tables_ = LoopTables{};
  for (SearchWorkspaces& w : workspaces_) w.release();
  std::vector<std::uint8_t>().swap(disabled_);
  mask_symmetric_ = true;
}

void LoopSession::check_graph() const {
  if (graph_released_) throw InputError("the loop engine's graph was released (the job was done with loop queries)");
}

template <typename F>
auto LoopSession::run_query(F&& query) {
  // Announce the new query first, so a running one sees its generation change
  // and gives up; then wait for the scratch space.
  const std::uint64_t mine = ++generation_;
  std::lock_guard<std::mutex> lock(query_mutex_);
  check_graph();
  if (generation_.load() != mine) throw Cancelled();
  query_limited_ = false;
  std::atomic<std::uint64_t> polls{0};
  const std::uint64_t limit = max_query_polls;
  SearchContext ctx{*surface_, graph_, disabled_, [this, mine, &polls, limit] {
                      if (generation_.load() != mine) throw Cancelled();
                      const std::uint64_t n = ++polls;
                      if (limit && n > limit) {
                        query_limited_ = true;
                        throw Cancelled();
                      }
                    }, mask_symmetric_};
  struct Count {  // the polls, however the query ends
    std::atomic<std::uint64_t>& polls;
    std::atomic<std::uint64_t>& last;
    ~Count() { last = polls.load(); }
  } count{polls, last_query_polls_};
  return query(ctx);
}

std::vector<Loop> LoopSession::loops(const std::vector<Anchor>& anchors, int count, bool allow_open) {
  return run_query([&](const SearchContext& ctx) {
    std::vector<ResolvedAnchor> resolved;
    for (size_t i = 0; i < anchors.size(); ++i)
      resolved.push_back(resolve_anchor(ctx, *locator_, anchors[i], max_anchor_distance, static_cast<int>(i)));
    LoopSearchOptions options;
    options.algorithm = algorithm;
    options.allow_open = allow_open;
    std::vector<Loop> result = find_loops(ctx, tables_, workspaces_, resolved, count, options);
    if (result.empty())
      throw InputError("no loop can meet these constraints: the anchors cannot be joined by a compatible loop");
    return result;
  });
}

Loop LoopSession::best_loop(const Vec3& point, bool allow_open) {
  return run_query([&](const SearchContext& ctx) {
    Anchor anchor;
    anchor.point = point;
    const ResolvedAnchor resolved = resolve_anchor(ctx, *locator_, anchor, max_anchor_distance, 0);
    LoopSearchOptions options;
    options.algorithm = algorithm;
    options.allow_open = allow_open;
    return best_loop_through(ctx, tables_, workspaces_, resolved, options);
  });
}

ResolvedAnchor LoopSession::resolve(const Anchor& anchor, int index) {
  check_graph();
  SearchContext ctx{*surface_, graph_, disabled_, nullptr};
  return resolve_anchor(ctx, *locator_, anchor, max_anchor_distance, index);
}

SurfacePath LoopSession::embed(const Loop& loop) const {
  check_graph();
  return embed_path(*surface_, graph_, loop.nodes, loop.closed);
}

// Changing the mask makes a running query stale: cancel it, then change.
void LoopSession::set_disabled(const std::vector<Index>& nodes, bool disabled) {
  ++generation_;
  std::lock_guard<std::mutex> lock(query_mutex_);
  check_graph();
  if (disabled_.empty()) disabled_.assign(graph_.num_nodes(), 0);
  for (Index n : nodes) {
    if (n < 0 || n >= graph_.num_nodes()) throw InputError("node id " + std::to_string(n) + " is not in the graph");
    disabled_[n] = disabled ? 1 : 0;
  }
  mask_symmetric_ = true;
  for (Index n = 0; n < graph_.num_nodes() && mask_symmetric_; ++n)
    mask_symmetric_ = disabled_[n] == disabled_[graph_.reverse[n]];
}

void LoopSession::clear_disabled() {
  ++generation_;
  std::lock_guard<std::mutex> lock(query_mutex_);
  disabled_.clear();
  mask_symmetric_ = true;
}

}  // namespace stripweave
