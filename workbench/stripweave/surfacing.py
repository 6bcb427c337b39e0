"""Stage 6, surfacing (beyond the paper): a design's quad layout refitted as
B-spline patches, sewn into a shell (a solid when closed), optionally STEP.

    ds = DesignSession(surface, Design.load("design.json"))
    result = refit_design(ds, step_path="out/patches.step")
    report["fit"] = fit_report(result)

refit_design returns the dict of the native `refit` (native/python/bind_surfacing.cpp):
lengths in model units; max_deviation, rms_deviation, per_patch, max_seam_gap,
max_seam_angle_deg (smooth seams), tolerance, tolerance_met, valid_shell, closed,
volume (None unless closed), faces, step_faces_read_back, timings_ms, time_s, ...
Keyword options go to the native fit (relative_tolerance, max_spans, seam_weight,
edge_smoothing, ...). Everything geometric happens in the native library.
"""
from ._native import native

FIT_KEYS = ("max_deviation", "rms_deviation", "max_seam_gap", "max_seam_angle_deg")
SHELL_KEYS = ("tolerance", "valid_shell", "closed", "volume", "faces")
PATCH_KEYS = ("max_deviation", "rms_deviation", "nu", "nv", "samples")


def refit_design(design_session, tolerance=None, step_path=None, **options):
    """Fit the design's layout: native.refit(surface, patch_network, ...).

    tolerance: model units (None: 1e-3 of the bbox diagonal). step_path: write
    STEP AP214 there (and read it back: "step_faces_read_back").
    Raises stripweave.InputError when the layout is invalid or has no patches.
    """
    network = design_session.native.patch_network()
    if not network["patches"]:
        raise native.InputError("the design's layout is not valid (red regions): no patches to fit")
    return native.refit(design_session.surface, network, tolerance=tolerance, step_path=step_path, **options)


def fit_report(result):
    """The "fit" block of report.json (design.md) from a refit result, model units."""
    fit = {k: float(result[k]) for k in FIT_KEYS}
    fit["per_patch"] = [{k: p[k] for k in PATCH_KEYS} for p in result["per_patch"]]
    fit["tolerance"] = float(result["tolerance"])
    fit["tolerance_met"] = bool(result["tolerance_met"])
    fit["valid_shell"] = bool(result["valid_shell"])
    fit["closed"] = bool(result["closed"])
    fit["volume"] = None if result["volume"] is None else float(result["volume"])
    fit["faces"] = int(result["faces"])
    return fit


def format_fit(fit):
    """One line for people."""
    shell = "closed solid" if fit["closed"] else "open shell"
    validity = "valid" if fit["valid_shell"] else "INVALID"
    volume = f", volume {fit['volume']:.6g}" if fit["volume"] is not None else ""
    return (f"fit: {fit['faces']} patches, max deviation {fit['max_deviation']:.3g} "
            f"(rms {fit['rms_deviation']:.3g}, tolerance {fit['tolerance']:.3g}), "
            f"seam gap {fit['max_seam_gap']:.3g}, seam angle {fit['max_seam_angle_deg']:.2f} deg; "
            f"{validity} {shell}{volume}")
