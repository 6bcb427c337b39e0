// DesignState (see design_state.h).
#include "stripweave/strips/design_state.h"

#include "stripweave/core/error.h"
#include "stripweave/core/stopwatch.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

namespace stripweave {

bool StripSpec::operator==(const StripSpec& o) const {
  if (anchors.size() != o.anchors.size()) return false;
  for (size_t i = 0; i < anchors.size(); ++i)
    if (anchors[i].point != o.anchors[i].point || anchors[i].direction != o.anchors[i].direction) return false;
  return true;
}

LoopPath loop_path(const LoopSession& session, const Loop& loop) {
  LoopPath p;
  p.path = session.embed(loop);
  p.closed = loop.closed;
  p.segments = path_segments(session.surface(), p.path, loop.closed);
  return p;
}

DesignState::DesignState(std::shared_ptr<LoopSession> session, const FieldOptions& options)
    : session_(std::move(session)), options_(options) {}

DesignState::Solved DesignState::solve(const std::vector<LoopPath>& paths, DesignTimings* timings,
                                       std::optional<KnownField> known) const {
  const Surface& s = session_->surface();
  if (failing_solves_ > 0) {
    --failing_solves_;
    throw std::runtime_error("a solve failed on purpose (fail_solves_for_test)");
  }
  Solved out;
  StageTimings laps;
  Stopwatch clock(laps);
  if (known) {
    out.field = std::move(known->field);
  } else {
    std::vector<std::vector<PathSegment>> segments;
    for (const LoopPath& p : paths) segments.push_back(p.segments);
    out.field = compute_cross_field(s, loop_constraints(segments), options_);
  }
  clock.lap("field");
  if (known) laps[0].second = known->ms;  // the time the field took when it was solved
  if (vertex_order_.empty()) vertex_order_ = vertex_elimination_order(s);
  out.param = parameterize(s, out.field, paths, vertex_order_);
  clock.lap("parameterization");
  for (Index l = 0; l < static_cast<Index>(paths.size()); ++l)
    out.strips.push_back(extract_strip(s, out.field, out.param, paths, l));
  clock.lap("extraction");
  if (timings) {
    timings->field_ms = laps[0].second;
    timings->param_ms = laps[1].second;
    timings->extraction_ms = laps[2].second;
  }
  return out;
}

namespace {

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
template <class T>
std::size_t bytes(const std::vector<std::vector<T>>& v) {
  std::size_t b = v.capacity() * sizeof(std::vector<T>);
  for (const auto& x : v) b += bytes(x);
  return b;
}

std::size_t bytes(const std::vector<DesignStrip>& strips) {
  std::size_t b = bytes<DesignStrip>(strips);
  for (const DesignStrip& d : strips) {
    const SurfacePath& p = d.path.path;
    b += bytes(d.spec.anchors) + bytes(d.loop.nodes) + bytes(p.points) + bytes(p.vertex) + bytes(p.edge) +
         bytes(p.t) + bytes(p.node_start) + bytes(d.path.segments);
    b += bytes(d.strip.covered) + bytes(d.strip.triangles) + bytes(d.strip.coords) + bytes(d.strip.isocurve);
  }
  return b;
}

// Whether `strips` are those of exactly the first `count` of `specs`.
bool strips_of(const std::vector<DesignStrip>& strips, const std::vector<StripSpec>& specs, std::size_t count) {
  return strips.size() == count && count <= specs.size() &&
         std::equal(strips.begin(), strips.end(), specs.begin(),
                    [](const DesignStrip& d, const StripSpec& s) { return d.spec == s; });
}

std::size_t bytes(const CrossField& f) {
  return bytes(f.frame_x) + bytes(f.normal) + bytes(f.theta) + bytes(f.direction) + bytes(f.strength) +
         bytes(f.constrained) + bytes(f.rho) + bytes(f.matching) + bytes(f.singularities);
}

std::size_t bytes(const Parameterization& p) {
  return bytes(p.uv) + bytes(p.comb) + bytes(p.transition) + bytes(p.on_cut) + bytes(p.loop_axis) +
         bytes(p.loop_value) + bytes(p.flipped) + bytes(p.cut_ends) + bytes(p.loop_points_uv);
}

}  // namespace

DesignState::MemoryBytes DesignState::memory_bytes() const {
  MemoryBytes m;
  m.strips = bytes(strips_);
  m.field = bytes(field_);
  m.param = bytes(param_);
  m.mask = bytes(mask_);
  for (const Derived* d : {&previous_, stashed_ ? &stashed_->derived : nullptr})
    if (d) m.previous += bytes(d->strips) + bytes(d->field) + bytes(d->param) + bytes(d->mask);
  return m;
}

void DesignState::swap_derived(Derived& d) {
  std::swap(strips_, d.strips);
  std::swap(field_, d.field);
  std::swap(param_, d.param);
  std::swap(timings_, d.timings);
  std::swap(mask_, d.mask);
}

void DesignState::set_strips(const std::vector<StripSpec>& specs) {
  // A session whose graph was released (LoopSession::release_graph) can derive
  // nothing: refused before anything derived is touched.
  session_->graph();
  if (restore_stashed(specs)) return;
  complete_ = false;
  // Back to the design before the last edit (a rejected strip removed): swap
  // the kept state back in, and keep the edited one in its place (redo).
  if (previous_.valid && strips_of(previous_.strips, specs, specs.size())) {
    swap_derived(previous_);
    session_->clear_disabled();
    complete_ = true;
    return;
  }
  // Nothing changed: every exit of set_strips leaves each strip kept fully
  // derived, field, S and mask those of exactly these strips.
  if (strips_of(strips_, specs, specs.size())) {
    session_->clear_disabled();
    complete_ = true;
    return;
  }
  // Keep the unchanged prefix: its loops and masks do not depend on later strips.
  size_t keep = 0;
  while (keep < specs.size() && keep < strips_.size() && specs[keep] == strips_[keep].spec) ++keep;
  const size_t derived = strips_.size();  // mask_ is the mask of these strips (finish())
  // The state before this edit, for going back to it. Moved, not copied: finish()
  // replaces the field, S and every strip's extraction anyway, so the edit keeps of
  // its prefix only the anchors, loops and paths (a copy of the extractions, each
  // some 50 bytes per surface triangle, was a third full design during the solve).
  previous_ = Derived{std::move(strips_), std::move(field_), std::move(param_), timings_, mask_, true};
  strips_.clear();
  field_ = {};
  param_ = {};
  for (size_t i = 0; i < keep; ++i) {
    DesignStrip d;
    d.spec = previous_.strips[i].spec;
    d.loop = previous_.strips[i].loop;
    d.path = previous_.strips[i].path;
    strips_.push_back(std::move(d));
  }

  double loops_ms = 0;
  std::vector<LoopPath> paths;
  // The field transversal_loop solved for `paths` as they stand, for the next solve
  // of exactly them (the prefix's mask, or finish()); taken once.
  std::optional<KnownField> known;
  auto take_known = [&known] {
    std::optional<KnownField> k = std::move(known);
    known.reset();
    return k;
  };
  for (const DesignStrip& d : strips_) paths.push_back(d.path);
  // On failure keep a consistent state: the strips before the failing one,
  // fully derived (those were solved already, as the failing strip's mask),
  // and name the strip in the error.
  // Rethrow the exception being handled after deriving the strips in paths (or, if
  // that fails too, none): every strip left has its extraction.
  auto throw_consistent = [&](std::vector<LoopPath>& kept, double ms) {
    try {
      finish(kept, ms);
    } catch (const std::exception&) {
      strips_.clear();
      kept.clear();
      finish(kept, 0);
    }
    throw;
  };
  // The strips before the failing one, derived: the state from before the edit
  // when they are its strips (a strip appended and refused, as automatic weaving
  // tries them), else solved again.
  auto fail = [&](size_t failing, const std::string& what) {
    session_->clear_disabled();
    strips_.resize(failing);
    paths.resize(failing);
    if (previous_.valid && strips_of(previous_.strips, specs, failing)) {
      swap_derived(previous_);
      previous_ = {};
      throw InputError("strip " + std::to_string(failing + 1) + ": " + what);
    }
    try {
      finish(paths, loops_ms);
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception&) {
      strips_.clear();
      paths.clear();
      finish(paths, 0);
    }
    throw InputError("strip " + std::to_string(failing + 1) + ": " + what);
  };
  for (size_t i = keep; i < specs.size(); ++i) {
    // The mask of strips 0..i-1, each extracted from the design so far. The
    // solve fails if strip i-1 contradicts the earlier ones (it crosses a
    // loop too tangentially for a parameterization to align with both).
    std::vector<Index> mask;
    if (i > 0) {
      // Appending to the derived design (automatic weaving, a click): its mask is
      // already that of strips 0..i-1; otherwise solve the prefix.
      if (i == keep && keep == derived) {
        mask = mask_;
      } else {
        try {
          mask = mask_of(paths, solve(paths, nullptr, take_known()).strips);
        } catch (const Cancelled&) {
          throw_consistent(paths, loops_ms);
        } catch (const std::exception& e) {
          fail(i - 1, e.what());
        }
      }
    }
    session_->clear_disabled();
    if (!mask.empty()) session_->set_disabled(mask, true);
    StageTimings laps;
    Stopwatch clock(laps);
    DesignStrip d;
    d.spec = specs[i];
    try {
      if (specs[i].anchors.empty()) throw InputError("it has no anchor");
      std::vector<Loop> found = session_->loops(specs[i].anchors, 1);
      if (found.empty()) throw InputError("no loop can pass its anchors with the current constraints");
      Transversal t = transversal_loop(specs[i], paths, std::move(found.front()));
      d.loop = std::move(t.loop);
      d.path = std::move(t.path);
      known = std::move(t.field);
    } catch (const InputError& e) {
      fail(i, e.what());
    } catch (...) {
      // Cancelled (or worse): the same consistent prefix, the error as it was.
      session_->clear_disabled();
      strips_.resize(i);
      paths.resize(i);
      throw_consistent(paths, loops_ms);
    }
    clock.lap("loop");
    loops_ms += laps.back().second;
    paths.push_back(d.path);
    strips_.push_back(std::move(d));
  }
  session_->clear_disabled();
  try {
    finish(paths, loops_ms, take_known());
  } catch (const Cancelled&) {
    // Cancelled inside the solve: no strip may stay without its extraction (a
    // reader of strip(i) would index an empty coverage), so back to no strips.
    strips_.clear();
    paths.clear();
    throw_consistent(paths, 0);
  } catch (const std::exception& e) {
    // Any failure of the solve (an InputError, or a numerical one such as a zero
    // pivot in the KKT factorization on a degenerate mesh) leaves the consistent
    // prefix: every strip kept is fully derived.
    if (strips_.empty()) throw;
    fail(strips_.size() - 1, e.what());
  }
  complete_ = true;
}

bool DesignState::restore_stashed(const std::vector<StripSpec>& specs) {
  if (!stashed_) return false;
  if (!strips_of(stashed_->derived.strips, specs, specs.size())) {
    stashed_.reset();
    return false;
  }
  if (stashed_->band != band_ || stashed_->angle_deg != angle_deg_) return false;
  swap_derived(stashed_->derived);
  stashed_.reset();
  previous_ = {};
  complete_ = true;
  session_->clear_disabled();
  return true;
}

// The compatibility mask is a prediction from the earlier strips'
// isocurves; the parameterization's meeting test, under the field of all
// loops, is the truth (parameterization.h, contradicting_meetings): a loop
// can still meet an earlier one too tangentially where a strip stops short of
// its loop (at a crease, beside a singularity) or where an embedded g-edge
// turns away from its nodes' directions. Each round disables the g' nodes
// from which the new loop departed into such a meeting (with their reversed
// nodes: the mask stays symmetric) and searches again through the same
// anchors. Of the loops tried, the first without such a meeting is taken,
// else the one with the fewest (the earliest among equals): the solve then
// names the meeting, as it did before. The rounds end early when no loop
// passes the anchors under the larger mask, or when a meeting does not
// involve the new loop (the new field made two earlier loops contradict).
// The extra nodes are this strip's only: set_strips clears the session's
// mask after each loop. Cost: one cut per added strip, and one field and cut
// per further round, only where the first loop meets another: the field of
// the loop kept is handed to the next solve of the same loops (KnownField),
// which does not solve it again.
DesignState::Transversal DesignState::transversal_loop(const StripSpec& spec, const std::vector<LoopPath>& paths,
                                                      Loop loop) {
  constexpr int kRounds = 4;
  const Surface& s = session_->surface();
  std::vector<LoopPath> all = paths;  // the earlier loops, then the one tried
  std::vector<std::vector<PathSegment>> segments;
  for (const LoopPath& p : paths) segments.push_back(p.segments);
  const Index fresh = static_cast<Index>(paths.size());
  Transversal best;
  size_t best_meetings = std::numeric_limits<size_t>::max();
  for (int round = 0;; ++round) {
    all.push_back(loop_path(*session_, loop));
    segments.push_back(all.back().segments);
    const auto start = std::chrono::steady_clock::now();
    CrossField field = compute_cross_field(s, loop_constraints(segments), options_);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const std::vector<LoopMeeting> meetings = contradicting_meetings(s, field, all);
    LoopPath path = std::move(all.back());
    all.pop_back();
    segments.pop_back();
    if (meetings.size() < best_meetings) {
      best_meetings = meetings.size();
      best = {loop, path, {std::move(field), ms}};
    }
    if (meetings.empty() || round == kRounds) break;
    std::vector<Index> nodes;
    const std::vector<Index>& starts = path.path.node_start;
    bool others = false;
    for (const LoopMeeting& m : meetings) {
      others |= m.loop_a != fresh && m.loop_b != fresh;
      for (const auto& [l, k] : {std::pair{m.loop_a, m.k_a}, std::pair{m.loop_b, m.k_b}}) {
        if (l != fresh) continue;
        // The g-edge whose embedding holds segment k starts at the last node start not after it.
        const auto it = std::upper_bound(starts.begin(), starts.end(), path.segments[k].from);
        const Index j = std::clamp<Index>(static_cast<Index>(it - starts.begin()) - 1, 0,
                                          static_cast<Index>(loop.nodes.size()) - 1);
        nodes.push_back(loop.nodes[j]);
        nodes.push_back(session_->graph().reverse[loop.nodes[j]]);
      }
    }
    if (others) break;
    session_->set_disabled(nodes, true);
    std::vector<Loop> again;
    try {
      again = session_->loops(spec.anchors, 1);
    } catch (const InputError&) {
      break;  // an anchor's own direction is now disabled: no other loop
    }
    if (again.empty()) break;
    loop = std::move(again.front());
  }
  return best;
}

void DesignState::finish(const std::vector<LoopPath>& paths, double loops_ms, std::optional<KnownField> known) {
  timings_ = {};
  timings_.loops_ms = loops_ms;
  mask_.clear();
  if (paths.empty()) {
    field_ = {};
    param_ = {};
    return;
  }
  Solved all = solve(paths, &timings_, std::move(known));
  // Derived once per edit, not per query: every hover applies it.
  mask_ = mask_of(paths, all.strips);
  field_ = std::move(all.field);
  param_ = std::move(all.param);
  for (size_t i = 0; i < strips_.size(); ++i) strips_[i].strip = std::move(all.strips[i]);
}

void DesignState::set_compatibility_angle(double degrees) {
  if (!(degrees > 0 && degrees < 90)) throw InputError("the compatibility angle must be within (0, 90) degrees");
  if (degrees != angle_deg_) rederive_all(band_, degrees);
}

void DesignState::set_compatibility_band(double band) {
  if (!(band > 0)) throw InputError("the compatibility band must be positive (or unbounded)");
  if (band != band_) rederive_all(band, angle_deg_);
}

void DesignState::rederive_all(double band, double angle_deg) {
  // Every prefix mask depends on the band and the angle: derive everything again
  // (from an empty, consistent state, so that nothing derived before is restored
  // as if derived under the new parameters). One state is kept: the one derived
  // under the new parameters if there is one (going back to them), else the
  // current one if complete (for going back to the old parameters); a partial one
  // (a failed derivation) never displaces a complete one.
  const bool back = stashed_ && stashed_->band == band && stashed_->angle_deg == angle_deg;
  if (!back && complete_ && !strips_.empty())
    stashed_ = Stashed{Derived{std::move(strips_), std::move(field_), std::move(param_), timings_, mask_, true},
                       band_, angle_deg_};
  band_ = band;
  angle_deg_ = angle_deg;
  strips_.clear();
  field_ = {};
  param_ = {};
  timings_ = {};
  mask_.clear();
  previous_ = {};
  complete_ = true;
}

std::vector<Index> DesignState::mask_of(const std::vector<LoopPath>& paths, const std::vector<Strip>& strips) const {
  std::vector<Index> mask;
  for (size_t i = 0; i < strips.size(); ++i) {
    const std::vector<Index> nodes =
        incompatible_nodes(session_->surface(), session_->graph(), strips[i], paths[i], angle_deg_, band_);
    mask.insert(mask.end(), nodes.begin(), nodes.end());
  }
  std::sort(mask.begin(), mask.end());
  mask.erase(std::unique(mask.begin(), mask.end()), mask.end());
  return mask;
}

void DesignState::apply_mask() {
  session_->clear_disabled();
  if (!mask_.empty()) session_->set_disabled(mask_, true);
}

}  // namespace stripweave
