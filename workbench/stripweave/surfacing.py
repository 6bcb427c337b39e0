"""Stage 6, surfacing (beyond the paper): a design's quad layout refitted as
B-spline patches, sewn into a shell (a solid when closed), optionally STEP.

    ds = DesignSession(surface, Design.load("design.json"))
    result = refit_design(ds, step_path="out/patches.step")
    report["fit"] = fit_report(result)

refit_design returns the dict of the native `refit` (native/python/bind_surfacing.cpp):
lengths in model units; the deviation two-sided (dense samples of the source against
every fitted patch and of every patch against the source, native fit_deviation.h):
max_deviation and rms_deviation (the larger of both directions),
max_deviation_source_to_patches, max_deviation_patches_to_source, their RMS, coverage
(the fraction of the source area within tolerance of a fitted patch), uncovered_area
(model units^2), per_patch (both directions each), max_seam_gap, max_seam_angle_deg
(smooth seams), tolerance, tolerance_met (both directions within tolerance and coverage
at least 0.999), valid_shell, closed, volume (None unless closed), faces,
step_faces_read_back, timings_ms, time_s, triangle_uncovered (per Surface triangle, the
uncovered fraction of its area: for deviation.png, never copied into report.json), ...,
and layout_patches / left_out_patches (layout patches that are not clean quads and so
were not fitted: their part of the source shows as uncovered).

Where the tolerance is missed, the per-patch figures say why (problem_of): a patch the
layout lays over a crease of the source (a C2 patch cannot follow it: the strips should
run along the feature curve), a fit that folds (turns its back on the source), or plain
accuracy (the spans ran out). Where the spans ran out, the patch's dual strip is split
along an isoline of its square map and fitted again (the native fit does it): "splits"
lists each, and per_patch then holds the pieces, each with its "layout_patch".
Keyword options go to the native fit (relative_tolerance, max_spans, seam_weight,
edge_smoothing, ...). Everything geometric happens in the native library.
"""
from ._native import native

# design.md's "fit" keys: the numbers (FIT_KEYS, floats in model units) and tolerance_met.
FIT_KEYS = ("max_deviation", "rms_deviation", "max_seam_gap", "max_seam_angle_deg",
            "max_deviation_source_to_patches", "max_deviation_patches_to_source",
            "rms_deviation_source_to_patches", "rms_deviation_patches_to_source",
            "tolerance", "coverage", "uncovered_area", "max_regular_seam_angle_deg")
DESIGN_FIT_KEYS = FIT_KEYS + ("tolerance_met",)
SHELL_KEYS = ("tolerance", "valid_shell", "closed", "volume", "faces")
PATCH_KEYS = ("max_deviation", "rms_deviation", "max_deviation_source_to_patch", "max_deviation_patch_to_source",
              "rms_deviation_source_to_patch", "rms_deviation_patch_to_source", "source_area",
              "fit_max_deviation", "nu", "nv", "samples", "side_deviation", "crease_deg",
              "crease_length", "creased", "flipped_fraction", "folded", "layout_patch", "even_stretch")
# A split of a dual strip where a patch missed the tolerance at its most spans (native
# split_strip.h): the patch, the layout patch it is, the isoline (direction "u": u = at),
# why, its deviation then, the patches the split crossed and their new pieces.
SPLIT_KEYS = ("patch", "layout_patch", "direction", "at", "reason", "deviation_before", "strip", "new_patches",
              "closed_strip", "round")
# Beyond design.md's: where the tolerance is missed and why, how the deviation was
# measured (samples, the bound on each measured distance's error, the patch tessellation's
# triangles (capped, native fit_deviation.h), the refinement's own
# measure at its fit samples), and the refit's own time.
EXTRA_KEYS = ("max_seam_angle_deg_regular", "max_edge_deviation", "max_deviation_uncreased",
              "tolerance_met_uncreased", "creased_patches", "folded_patches", "source_area", "source_samples",
              "patch_samples", "unsampled_faces", "measurement_error", "patch_triangles", "fit_max_deviation",
              "time_s")


def refit_design(design_session, tolerance=None, step_path=None, set_aside_red=False, **options):
    """Fit the design's layout: native.refit(surface, patch_network, ...).

    tolerance: model units (None: 1e-3 of the bbox diagonal). step_path: write
    STEP AP214 there (and read it back: "step_faces_read_back"). set_aside_red:
    where a region stays red, fit the components that hold none (native
    layout/set_aside.h); coverage and deviations stay those of the whole surface.
    Raises stripweave.InputError when the layout is invalid or has no patches.
    """
    network = design_session.native.patch_network(set_aside_red)
    if not network["patches"]:
        made = int(network.get("layout_patches", 0))
        if made:
            which = "the layout's only patch is not" if made == 1 else f"none of the layout's {made} patches is"
            raise native.InputError(f"{which} a clean quad (see the problems in layout.json): no patches to fit")
        raise native.InputError("the design's layout has no patch (red regions remain, or no two strips cross): "
                               "no patches to fit")
    result = native.refit(design_session.surface, network, tolerance=tolerance, step_path=step_path, **options)
    result["layout_patches"] = int(network.get("layout_patches", len(network["patches"])))
    result["left_out_patches"] = result["layout_patches"] - len(network["patches"])
    return result


def problem_of(patch, tolerance):
    """Why a patch misses the tolerance, in words ("" when it meets it)."""
    if patch["max_deviation"] <= tolerance and patch.get("side_deviation", 0.0) <= tolerance:
        return ""
    if patch.get("creased"):
        return (f"layout: the patch lies over a crease ({patch['crease_deg']:.0f} deg, "
                f"{patch['crease_length']:.3g} long); its strips should run along the feature curve")
    if patch.get("folded"):
        return f"fit folds: {100 * patch['flipped_fraction']:.1f}% of the patch faces away from the source"
    if (patch.get("max_deviation_patch_to_source", 0.0) <= tolerance
            and patch.get("max_deviation_source_to_patch", 0.0) > tolerance):
        return ("coverage: source next to the patch lies off every fitted patch "
                "(a layout patch left out, or a gap between patches)")
    return f"accuracy: {patch['nu']} x {patch['nv']} spans were not enough"


def fit_report(result):
    """The "fit" block of report.json (design.md) from a refit result, model units."""
    # The regular-seam figure under design.md's name (the native one is kept too).
    fit = {k: float(result["max_seam_angle_deg_regular" if k == "max_regular_seam_angle_deg" else k])
           for k in FIT_KEYS}
    fit["per_patch"] = [{**{k: p[k] for k in PATCH_KEYS}, "problem": problem_of(p, result["tolerance"])}
                        for p in result["per_patch"]]
    fit.update({k: result[k] for k in EXTRA_KEYS})
    for key in ("splits", "rejected_splits"):
        fit[key] = [{k: s[k] for k in SPLIT_KEYS} for s in result.get(key, [])]
    # With the weave's symmetries (native symmetric_fit.h): whether the layout paired under
    # all of them, and the largest distance between mapped control points and their image's
    # as fitted independently and as written (model units).
    if result.get("symmetric") is not None:
        fit["symmetric"] = bool(result["symmetric"])
        for key in ("symmetry_error", "symmetry_error_fit"):
            fit[key] = None if result[key] is None else float(result[key])
        if result.get("symmetry_problem"):
            fit["symmetry_problem"] = result["symmetry_problem"]
    fit["left_out_patches"] = int(result.get("left_out_patches", 0))
    fit["tolerance"] = float(result["tolerance"])
    fit["tolerance_met"] = bool(result["tolerance_met"])
    fit["valid_shell"] = bool(result["valid_shell"])
    fit["closed"] = bool(result["closed"])
    fit["shells"] = int(result["shells"])
    fit["solids"] = int(result["solids"])
    fit["volume"] = None if result["volume"] is None else float(result["volume"])
    fit["faces"] = int(result["faces"])
    return fit


def format_fit(fit):
    """One line for people."""
    solids = fit.get("solids", 1 if fit["closed"] else 0)
    shell = ("closed solid" if solids == 1 else f"{solids} closed solids") if fit["closed"] else \
        ("open shell" if not solids else f"{solids} solids and {fit.get('shells', solids) - solids} open shell(s)")
    validity = "valid" if fit["valid_shell"] else "INVALID"
    volume = f", volume {fit['volume']:.6g}" if fit["volume"] is not None else ""
    line = (f"fit: {fit['faces']} patches, max deviation {fit['max_deviation']:.3g} "
            f"(source to patches {fit['max_deviation_source_to_patches']:.3g}, patches to source "
            f"{fit['max_deviation_patches_to_source']:.3g}; rms {fit['rms_deviation']:.3g}; "
            f"tolerance {fit['tolerance']:.3g}), coverage {100 * fit['coverage']:.2f}% "
            f"(uncovered {fit['uncovered_area']:.3g}), "
            f"seam gap {fit['max_seam_gap']:.3g}, seam angle {fit['max_seam_angle_deg']:.2f} deg; "
            f"{validity} {shell}{volume}")
    missed = [i for i, p in enumerate(fit["per_patch"]) if p.get("problem")]
    creased = [i for i in missed if fit["per_patch"][i].get("creased")]
    if missed:
        line += f"; {len(missed)} patches miss the tolerance"
        if creased:
            line += f", {len(creased)} of them lie over a crease (layout: {', '.join(map(str, creased[:8]))}"
            line += ", ...)" if len(creased) > 8 else ")"
    if fit.get("splits"):
        line += f"; {len(fit['splits'])} strip splits ({len(fit['per_patch'])} patches fitted)"
    if fit.get("left_out_patches"):
        line += f"; {fit['left_out_patches']} layout patches are not clean quads and were left out"
    return line
