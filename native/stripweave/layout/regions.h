// The regions of a loop arrangement and their assessment (paper §4.2): the
// pieces the dual loops cut the surface into, each the dual of one vertex of
// the primal quad layout (§7).
//
// compute_regions(surface, arrangement, singularities) -> Regions
//   Input : the surface, its loop arrangement (loop_arrangement.h), and the
//           cross field's singularities (cross_field.h; may be empty).
//   Method and conventions:
//     region     a connected component of refined triangles across edges
//                that are neither on a loop nor on the open boundary.
//     topology   of the region cut open along the loops (a loop that has the
//                region on both sides, like a lone meridian on a torus,
//                bounds it twice): chi = V - E + F of the cut-open region,
//                boundaries = its boundary cycles, genus = (2 - chi - b) / 2;
//                a disc iff chi = 1 (then b = 1, genus 0).
//     valence    the number of sides: along each boundary cycle, the number
//                of corners, a corner being where the cycle leaves one curve
//                for another: at a crossing of two loops (or of a loop with
//                itself), where a loop meets the open boundary (an open dual
//                curve's end), where loops touch. A boundary cycle without
//                corners (a lone closed loop, a boundary loop no curve ends
//                on) adds nothing. The open boundary between two
//                consecutive curve ends is thus one side however it turns:
//                the corners of a square sheet do not split sides; their
//                turn is curvature (below). Sharp feature curves are not
//                sides either: they are not layout edges, and their
//                curvature is in K through the angle defects at their
//                vertices (a cube corner is pi/2 of K).
//     open_sides the sides along the open boundary (counted on cycles with
//                corners: a stretch of boundary between two curve ends).
//                The primal layout is aligned to the boundary (§5.7, §7):
//                a region that touches it gets its vertex there, and the
//                primal edges across the arcs ending beside it run along
//                the boundary to the next boundary vertices. One vertex
//                closes the patches along ONE stretch only: a region with
//                two or more (the band beside a dual curve that crosses
//                nothing, a tube cut from end to end) leaves the others in
//                no patch (layout_defects.h: uncovered). It is still a
//                disc, valid in the paper's sense; weaving parts its
//                stretches (weave_seeds.h: bridge_anchors, weave.py).
//     on_open_boundary  some of its boundary is open boundary. A disc of
//                valence 0 is either a cap (its one boundary cycle a closed
//                loop that crosses nothing) or a sheet no curve has reached
//                yet (its cycle the open boundary): the same valence,
//                open_sides 0, and only this tells them apart. A cap's
//                vertex has no primal edge (no patch covers it) and a loop
//                across it mends that; a sheet needs its first curve.
//     total_curvature  K = the Gaussian curvature inside plus the geodesic
//                curvature of the region's open-boundary sides (including
//                the turn at boundary corners), so that for a disc whose
//                loops are geodesics meeting each other and the boundary at
//                right angles Gauss-Bonnet gives exactly K = (4 - v) pi / 2.
//                Discretely: the angle defect of each surface vertex
//                (2 pi - angle sum inside, pi - angle sum on the open
//                boundary) is shared among the regions around it in
//                proportion to the angle each has there (refined triangles'
//                corner angles). So a vertex inside a region gives it its
//                whole defect, a vertex exactly on a loop splits its defect
//                by angle, and the loops' own geodesic curvature is in no
//                region. The shares add up to the vertex's defect, so the
//                regions' K add up to 2 pi chi(surface).
//     singularities  each singularity belongs to the region with the
//                largest angle at its vertex (the one it lies inside, or on
//                a loop the side it mostly faces).
//     area       of the refined triangles (normalized units squared).
//     creases    crease_structure (crease_structure.h): whether the region
//                can carry its creases on primal edges, and its crease node.
//     colour     assess_region (assessment.h).
//     set_aside  the region lies on a surface triangle the optional
//                `set_aside` mask (per surface triangle) marks: a component
//                left out of the layout (set_aside.h), whose loops the
//                caller left out too.
//   Output: per refined triangle its region; per region the above; per arc
//           of the arrangement its left and right region; valid iff no
//           region but a set-aside one is red; euler_sum = graph V - E + sum of the regions' chi,
//           which equals chi(surface) (a check of the whole construction).
#pragma once

#include "stripweave/layout/assessment.h"
#include "stripweave/layout/crease_structure.h"
#include "stripweave/layout/loop_arrangement.h"

namespace stripweave {

struct Region {
  Index triangles = 0;  // refined triangles
  double area = 0;      // normalized units squared
  int euler_characteristic = 0;
  int boundaries = 0;
  int genus = 0;
  bool disc = false;
  int valence = 0;
  int open_sides = 0;  // sides along the open boundary (above)
  bool on_open_boundary = false;  // some boundary edge is open boundary (above)
  double total_curvature = 0;
  std::vector<Index> singularities;  // indices into the input singularities
  int excess_extrema = 0;            // curvature extrema of one kind beyond the first (assessment.h)
  CreaseProblem crease_problem = CreaseProblem::None;  // crease_structure.h
  int crease_excess = 0;                               // ... and how far from carrying its creases
  int crease_rim_lack = 0;                             // crossings rims lack, counted here (crease_rims.h)
  RegionColour colour = RegionColour::None;
  bool set_aside = false;  // on a component left out of the layout (above)
};

struct Regions {
  std::vector<Index> triangle_region;  // per refined triangle
  std::vector<Region> regions;
  std::vector<Index> arc_left, arc_right;  // per arc, kInvalid on an open boundary
  bool valid = false;
  int euler_sum = 0;
  CreaseStructure creases;  // what the creases ask of each region and arc (crease_structure.h)
};

Regions compute_regions(const Surface& surface, const LoopArrangement& arrangement,
                        const std::vector<Singularity>& singularities,
                        const std::vector<std::uint8_t>& set_aside = {});

}  // namespace stripweave
