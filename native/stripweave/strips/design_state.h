// DesignState: everything derived from a design (paper §4.1, §6).
//
// A design is an ordered list of strips, each given by its anchors (the
// truth the user edits and the file stores); its loop is derived. Given the
// strips, DesignState derives, in order:
//   loops      strip i's loop is the best loop through its anchors under the
//              compatibility mask of strips 0..i-1 (§6.2): it crosses every
//              earlier strip transversally and never repeats one;
//   field      the cross field constrained by all loops (and by features and
//              aligned boundaries, cross_field.h), with its singularities;
//   S          the global parameterization in which every loop is an
//              isocurve (parameterization.h);
//   strips     per loop, the strip it owns (strip_extraction.h);
//   mask       the union of the strips' incompatible g' nodes, which
//              apply_mask() hands to the LoopSession for the next loop.
// The mask predicts from the earlier strips where a loop would run along
// them; the loop actually found is checked by the parameterization's own
// meeting test (contradicting_meetings, parameterization.h), and where it
// still meets an earlier loop or itself too tangentially, the g' nodes it
// left from there are disabled too and it is searched again.
// Editing (set_strips) recomputes from the first strip that changed: the
// loops before it, and the masks they imply, are kept. Each strip i > 0 costs
// one field and parameterization solve over loops 0..i-1 (its mask), and the
// full design one more. Going back to the design before the last edit (a strip
// tried and removed again, as automatic weaving does for every rejected
// proposal) restores the state kept from before that edit instead of solving
// again: the solve is a function of the loops, so the result is the same;
// a strip appended and refused (InputError) leaves that state in place, and
// set_strips of the strips as they stand solves nothing.
// Likewise a change of the mask's parameters (band, angle) keeps the state
// derived under the old ones: changed back before the strips change (weaving
// tries a band and may keep the paper's mask, weave.py), the same strips take
// it back instead of deriving every strip again.
// Errors: InputError naming the strip ("strip 3: ...") for an anchor off
// the surface or constraints no loop can meet.
#pragma once

#include "stripweave/elastica/loop_session.h"
#include "stripweave/strips/edge_route.h"
#include "stripweave/strips/compatibility.h"
#include "stripweave/symmetry/symmetry.h"

#include <memory>
#include <optional>

namespace stripweave {

struct StripSpec {
  std::vector<Anchor> anchors;  // normalized units
  bool operator==(const StripSpec& o) const;
};

struct DesignStrip {
  StripSpec spec;
  Loop loop;
  LoopPath path;
  Strip strip;
};

struct DesignTimings {
  double loops_ms = 0, field_ms = 0, param_ms = 0, extraction_ms = 0;
};

class DesignState {
 public:
  DesignState(std::shared_ptr<LoopSession> session, const FieldOptions& options = {});

  void set_strips(const std::vector<StripSpec>& specs);
  const std::vector<DesignStrip>& strips() const { return strips_; }
  // Test entry: the next `count` solves fail as a numerical error would (a
  // std::runtime_error, as a zero pivot in the KKT factorization does), to
  // check that set_strips leaves every strip it keeps fully derived.
  void fail_solves_for_test(int count) { failing_solves_ = count; }
  const CrossField& field() const { return field_; }
  const Parameterization& parameterization() const { return param_; }
  // The final solve and extraction over the whole design (not the prefixes).
  const DesignTimings& timings() const { return timings_; }

  // How far from its loop a strip disables parallel directions (model
  // units, as the strip coordinates; infinity, the default, is the paper's whole strip). Changing it
  // re-derives every strip at the next set_strips.
  void set_compatibility_band(double band);
  double compatibility_band() const { return band_; }
  // Within that band, a g' node is refused if its direction is within this
  // angle (degrees, in (0, 90)) of the strip's loop direction: 45, the
  // default, is the paper's; more asks later loops to cross the strip closer
  // to a right angle. Changing it re-derives every strip at the next set_strips.
  void set_compatibility_angle(double degrees);
  double compatibility_angle() const { return angle_deg_; }

  // Primal vertices the user placed (paper §7: a vertex is dragged within
  // its region), normalized units: each moves its region's vertex to the
  // point of the region nearest it (primal_vertices.cpp). Not derived state:
  // the loops, field and strips do not depend on them, only the layout.
  void set_vertex_pins(std::vector<Vec3> pins) { pins_ = std::move(pins); }
  const std::vector<Vec3>& vertex_pins() const { return pins_; }
  // Primal edges the user routed by hand (paper §7: where in its corridor a
  // patch boundary lies), normalized units (quad_layout.h, EdgeRoute). The
  // layout's alone, like the pins.
  void set_edge_routes(std::vector<EdgeRoute> routes) { edge_routes_ = std::move(routes); }
  const std::vector<EdgeRoute>& edge_routes() const { return edge_routes_; }
  // The symmetries the design accepted (paper §5.8), normalized units: the
  // layout puts the vertices of regions that are each other's images at
  // each other's images (primal_vertex_symmetry.cpp). The layout's alone,
  // like the pins: the strips' images are added by the caller.
  void set_layout_symmetries(std::vector<Symmetry> s) { layout_symmetries_ = std::move(s); }
  const std::vector<Symmetry>& layout_symmetries() const { return layout_symmetries_; }

  // The compatibility mask of all strips, sorted node ids.
  const std::vector<Index>& disabled_nodes() const { return mask_; }
  // Hand that mask to the session (replacing its mask), for new loops.
  void apply_mask();

  // Heap bytes of the derived state (strips with their loops, paths and
  // extraction; cross field; parameterization; mask), now and as kept from
  // before the last edit: what a design holds beside the loop engine.
  struct MemoryBytes {
    std::size_t strips = 0, field = 0, param = 0, mask = 0, previous = 0;
  };
  MemoryBytes memory_bytes() const;

  LoopSession& session() { return *session_; }
  const LoopSession& session() const { return *session_; }
  const Surface& surface() const { return session_->surface(); }

 private:
  // Everything set_strips derives, kept from before the last edit (undo).
  struct Derived {
    std::vector<DesignStrip> strips;
    CrossField field;
    Parameterization param;
    DesignTimings timings;
    std::vector<Index> mask;
    bool valid = false;
  };
  void swap_derived(Derived& d);
  // The mask's parameters change to (band, angle): everything derived is set
  // aside in stashed_ (if complete) and derived again at the next set_strips.
  void rederive_all(double band, double angle_deg);
  // Take the stashed state back if it was derived for exactly these specs under
  // the current parameters; forget it once the strips differ from its own.
  bool restore_stashed(const std::vector<StripSpec>& specs);

  struct Solved {
    CrossField field;
    Parameterization param;
    std::vector<Strip> strips;
  };
  // The cross field of a loop set, already solved (by transversal_loop) for the
  // solve that follows it, with the time it took.
  struct KnownField {
    CrossField field;
    double ms = 0;
  };
  // `known`, when given, is the field of exactly these paths: not solved again.
  Solved solve(const std::vector<LoopPath>& paths, DesignTimings* timings,
               std::optional<KnownField> known = std::nullopt) const;
  // Derive field, S and strips of the whole design (the loops are known).
  void finish(const std::vector<LoopPath>& paths, double loops_ms, std::optional<KnownField> known = std::nullopt);
  // The union of the strips' incompatible nodes, sorted.
  std::vector<Index> mask_of(const std::vector<LoopPath>& paths, const std::vector<Strip>& strips) const;
  // The loop found for `spec` under the session's mask, searched again where
  // it meets an earlier loop (of `paths`) or itself too tangentially (see
  // design_state.cpp); with its path, and in `field` the cross field of
  // `paths` and that loop (the next solve of exactly those paths reuses it).
  struct Transversal {
    Loop loop;
    LoopPath path;
    KnownField field;
  };
  Transversal transversal_loop(const StripSpec& spec, const std::vector<LoopPath>& paths, Loop loop);

  std::shared_ptr<LoopSession> session_;
  FieldOptions options_;
  double band_ = std::numeric_limits<double>::infinity();
  double angle_deg_ = 45.0;
  std::vector<DesignStrip> strips_;
  std::vector<Vec3> pins_;
  std::vector<EdgeRoute> edge_routes_;
  std::vector<Symmetry> layout_symmetries_;
  CrossField field_;
  Parameterization param_;
  DesignTimings timings_;
  std::vector<Index> mask_;  // disabled_nodes(), derived with the strips
  Derived previous_;         // the derived state before the last edit
  // The complete derived state under other mask parameters (rederive_all).
  struct Stashed {
    Derived derived;
    double band = 0, angle_deg = 0;
  };
  std::optional<Stashed> stashed_;
  // Whether strips_ holds every strip of the last set_strips, derived: only
  // such a state is stashed (a failed derivation keeps a prefix).
  bool complete_ = true;
  // The surface's elimination order for S (parameterization.h), computed at
  // the first solve: it depends on the mesh alone.
  mutable std::vector<Index> vertex_order_;
  mutable int failing_solves_ = 0;  // fail_solves_for_test
};

// The loop path of a loop: embedded and cut into per-triangle segments.
LoopPath loop_path(const LoopSession& session, const Loop& loop);

}  // namespace stripweave
