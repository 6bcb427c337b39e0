// LoopSession: the interactive loop engine over one surface (paper §4.1, §5).
//
// Owns the elastica graph, a locator for anchors, the mask of disabled g'
// nodes (strip compatibility, §6.2) and the search scratch space. Built once
// per surface and parameters; every query after that is output-sensitive.
//
// Threading: queries may come from any thread and release the Python GIL. A
// newer query cancels an older one still running (it raises Cancelled), so
// the hover tool always works on the latest cursor position. The mask can be
// changed between queries, incrementally, without rebuilding anything.
//
// All points here are in normalized units; the bindings convert.
#pragma once

#include "stripweave/elastica/embed_path.h"
#include "stripweave/elastica/loop_search.h"

#include <atomic>
#include <memory>
#include <mutex>

namespace stripweave {

class SurfaceLocator;

class LoopSession {
 public:
  LoopSession(std::shared_ptr<const Surface> surface, const ElasticaParams& params, Progress* progress = nullptr);
  ~LoopSession();

  const Surface& surface() const { return *surface_; }
  // InputError once the graph is released (release_graph).
  const ElasticaGraph& graph() const {
    check_graph();
    return graph_;
  }
  double build_ms() const { return build_ms_; }

  // Anchors farther than this from the surface are an error (normalized units).
  double max_anchor_distance = 0.01;
  SearchAlgorithm algorithm = SearchAlgorithm::Bidirectional;
  // Threads a query may use (the machines have two cores).
  void set_threads(int threads);
  int threads() const { return static_cast<int>(workspaces_.size()); }
  // The search scratch space: 20 bytes per g' node and workspace, two
  // workspaces per thread (bidirectional), allocated by the first query and
  // kept for the next (on 30K triangles some 70 MB, as much as g' itself).
  std::size_t workspace_bytes() const;
  // Free it (a running query is cancelled first): a job done with queries
  // keeps the graph alone. The next query allocates it again; results do
  // not change.
  void release_workspaces();
  // Free g' with everything built on it (search tables, scratch space, mask):
  // a job done with loop queries keeps the derived design (paths, strips),
  // and the layout, pictures and fit need nothing of the graph. Every later
  // use of the graph (a query, an embedding, a mask, graph()) raises
  // InputError; the session is not rebuilt.
  void release_graph();
  bool graph_released() const { return graph_released_; }

  // The loops through the anchors, cheapest first, at most `count` distinct.
  std::vector<Loop> loops(const std::vector<Anchor>& anchors, int count, bool allow_open = true);
  // Hover: the best loop through a point over all directions.
  Loop best_loop(const Vec3& point, bool allow_open = true);
  // The loop embedded on the surface.
  SurfacePath embed(const Loop& loop) const;

  // Anchor resolution on its own (for tests and tools).
  ResolvedAnchor resolve(const Anchor& anchor, int index = 0);

  // The compatibility mask.
  void set_disabled(const std::vector<Index>& nodes, bool disabled);
  void clear_disabled();
  const std::vector<std::uint8_t>& disabled() const { return disabled_; }

  // Cancel the running query, if any.
  void cancel() { ++generation_; }

  // A deterministic cap on a query's work: past this many cancellation polls
  // (one per 4096 settled g' nodes) the query raises Cancelled and
  // query_limited() is true until the next query. 0: no cap. Why: automatic
  // weaving must give the same design on any machine, so it cannot stop a
  // hopeless query (no compatible loop through a point, every direction
  // searched to the end) by the clock. The count is exact with one thread;
  // with two it depends on how the threads share the starts.
  std::uint64_t max_query_polls = 0;
  bool query_limited() const { return query_limited_; }
  std::uint64_t last_query_polls() const { return last_query_polls_; }

 private:
  template <typename F>
  auto run_query(F&& query);
  void check_graph() const;
  std::atomic<bool> graph_released_{false};

  std::shared_ptr<const Surface> surface_;
  ElasticaGraph graph_;
  std::unique_ptr<SurfaceLocator> locator_;
  LoopTables tables_;
  std::vector<std::uint8_t> disabled_;
  bool mask_symmetric_ = true;
  std::vector<SearchWorkspaces> workspaces_;  // one per search thread
  mutable std::mutex query_mutex_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<bool> query_limited_{false};
  std::atomic<std::uint64_t> last_query_polls_{0};
  double build_ms_ = 0;
};

}  // namespace stripweave
