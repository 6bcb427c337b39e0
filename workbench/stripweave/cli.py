"""The `stripweave` command line (run it as build/stripweave).

    stripweave info MODEL [--json] [--symmetry auto]   the surface report (and its symmetries)
    stripweave loop MODEL --anchor X,Y,Z[,DX,DY,DZ] [--anchor ...] [--alternatives K]
                    [--boundary aligned|trimmed] [--json]   elastica loops through anchors
                    [--design D.json]   ... compatible with the design's strips (§6.2)
    stripweave strips MODEL --design D.json --out DIR [--json]
                                         cross field, parameterization and strips -> DIR/strips.json
    stripweave layout MODEL --design D.json --out DIR [--json]
                                         regions, assessment and primal quad layout -> DIR/layout.json
    stripweave weave MODEL [--design D.json] [--auto] --out DIR [--step] [--json]
                    [--max-strips N] [--patches N] [--no-features] [--boundary aligned|trimmed] [--seed S]
                    [--time-limit S] [--symmetry auto|none|reflect:..|rotate:..] [--symmetry-tolerance F]
                                         the main job: (automatic) design, layout, report, preview.png
    stripweave bench MODEL [--repeat N] [--no-refit] [--job]  stage timings, sizes and memory (refit_s too), JSON
    stripweave bench --scale [--sizes N,N,..] [--keep DIR] [--no-weave]
                                         large inputs: ingest against numpy, proxy, hover, weave, peak
                                         memory on a generated torus (bench_scale.py), JSON
    stripweave batch MODEL_OR_DIR... --out OUT [--step] [--jobs N] [--time-limit S] [--memory-limit MB]
                    [--scheduler ADDRESS] [--target-triangles N] [--budget UNITS] ...
                                         weave every model, one process each -> OUT/summary.json, .md,
                                         index.html (batch.py)

MODEL is STEP/STP, IGES/IGS, BREP/BRP, STL, OBJ, OFF, PLY, or an FCStd with
one shape or mesh. Bad input ends with a one-line error and exit status 1.
"""
import argparse
import json
import os
import sys


def _add_surface_options(p):
    g = p.add_argument_group("surface options")
    g.add_argument("--target-triangles", type=int, default=30000,
                   help="size of the solver mesh (0 keeps the tessellation or input mesh)")
    g.add_argument("--feature-angle", type=float, default=None,
                   help="dihedral angle in degrees above which an edge is a sharp feature (default 30, "
                        "or the design's)")
    g.add_argument("--deflection", type=float, default=0.0,
                   help="B-rep chordal deflection in model units (default: 1e-3 of the diagonal)")
    g.add_argument("--memory-limit", type=float, default=None, metavar="MB", dest="memory_guard_mb",
                   help="refuse work estimated to need more memory than this, before it starts (default: "
                        "MemAvailable of /proc/meminfo; also the STRIPWEAVE_MEMORY_LIMIT_MB variable)")


def _surface_options(args):
    return {"target_triangles": args.target_triangles,
            "feature_angle_deg": 30.0 if args.feature_angle is None else args.feature_angle,
            "deflection": args.deflection}


def cmd_info(args):
    from .report import format_report, info_dict
    from .surface import load
    surface = load(args.model, **_surface_options(args))
    info = info_dict(surface)
    if args.symmetry != "none":
        import time
        from .symmetry import resolve
        start = time.perf_counter()
        info["symmetry"] = resolve(surface, args.symmetry, tolerance=args.symmetry_tolerance)
        info["symmetry_time_ms"] = round((time.perf_counter() - start) * 1000.0, 1)
    if args.json:
        print(json.dumps(info, indent=2))
    else:
        print(format_report(info))
    return 0


def _surface_options_for(args, design):
    """Surface options: the command line's, except the feature angle a design was made with
    when the command line leaves it at its default."""
    options = _surface_options(args)
    if design is not None and args.feature_angle is None:
        options["feature_angle_deg"] = design.options["feature_angle_deg"]
    return options


def _design_session(args, surface, design):
    from .strips import DesignSession
    from .symmetry import symmetric_surface
    if args.boundary is not None:
        design.options["boundary"] = args.boundary
    # A symmetric design was derived on the symmetric solver mesh (weave --symmetry).
    return DesignSession(symmetric_surface(surface, design.symmetry or ()), design)


def cmd_loop(args):
    from .design import Design
    from .loops import LoopSession, parse_anchor, timed
    from .surface import load
    anchors = [parse_anchor(a) for a in args.anchor]
    design = Design.load(args.design) if args.design else None
    surface = load(args.model, **_surface_options_for(args, design))
    if design is not None:
        session = _design_session(args, surface, design)
        loops, ms = timed(session.loops, anchors, alternatives=args.alternatives)
        stats = session.loop_session.stats()
    else:
        session = LoopSession(surface, boundary=args.boundary or "aligned")
        loops, ms = timed(session.loops, anchors, alternatives=args.alternatives)
        stats = session.stats()
    keys = ("cost", "length", "closed", "points", "max_turn_deg", "length_term", "alignment_term", "curvature_term")
    if args.json:
        print(json.dumps({"loops": [{k: loop[k] for k in keys} for loop in loops], "time_ms": ms}))
    else:
        for i, loop in enumerate(loops):
            kind = "loop" if loop["closed"] else "open curve"
            print(f"{i + 1}. {kind}: length {loop['length']:.6g}, cost {loop['cost']:.4g} "
                  f"(length {loop['length_term']:.4g}, alignment {loop['alignment_term']:.4g}, "
                  f"curvature {loop['curvature_term']:.4g}), max turn {loop['max_turn_deg']:.1f} deg, "
                  f"{len(loop['points'])} points")
        print(f"search took {ms:.1f} ms (graph built in {stats['graph_build_s']:.2f} s)")
    return 0


def cmd_strips(args):
    from .design import Design
    from .files import write_atomic
    from .surface import load
    design = Design.load(args.design)
    surface = load(args.model, **_surface_options_for(args, design))
    session = _design_session(args, surface, design)
    result = session.strips_json()
    path = write_atomic(os.path.join(args.out, "strips.json"), json.dumps(result))
    if args.json:
        print(json.dumps({k: v for k, v in result.items() if k != "strips"} |
                         {"strips": [{k: v for k, v in s.items() if k != "points"} for s in result["strips"]],
                          "path": path}))
        return 0
    for i, s in enumerate(result["strips"]):
        kind = "loop" if s["closed"] else "open curve"
        print(f"strip {i + 1}: {kind} of length {s['length']:.6g}, width {s['width_left']:.4g} left "
              f"({s['stop_left']}) + {s['width_right']:.4g} right ({s['stop_right']}), "
              f"covers {100 * s['area_fraction']:.1f}% of the surface")
    quarters = {}
    for x in result["singularities"]:
        quarters[x["index"]] = quarters.get(x["index"], 0) + 1
    listed = ", ".join(f"{n} of index {i:+g}" for i, n in sorted(quarters.items())) or "none"
    print(f"singularities: {listed} (sum {result['index_sum']:g}, Euler characteristic "
          f"{result['euler_characteristic']})")
    print(f"fold-overs: {result['fold_overs']}")
    t = result["timings_ms"]
    print(f"loops {t['loops']:.0f} ms, field {t['field']:.0f} ms, parameterization {t['parameterization']:.0f} ms, "
          f"extraction {t['extraction']:.0f} ms")
    print(f"wrote {path}")
    return 0


def cmd_layout(args):
    from .design import Design
    from .layout import compute_layout, format_summary, write_layout
    from .surface import load
    design = Design.load(args.design)
    surface = load(args.model, **_surface_options_for(args, design))
    session = _design_session(args, surface, design)
    result = compute_layout(session)
    path = write_layout(result, os.path.join(args.out, "layout.json"))
    if args.json:
        colours = {}
        for r in result["regions"]:
            colours[r["colour"]] = colours.get(r["colour"], 0) + 1
        print(json.dumps({"valid": result["valid"], "clean": result["clean"], "defects": result["defects"],
                          "crease_conformity": result["crease_conformity"],
                          "regions": colours, "summary": result["summary"],
                          "problems": result["problems"], "timings_ms": result["timings_ms"], "path": path}))
    else:
        print(format_summary(result))
        print(f"wrote {path}")
    return 0


def cmd_bench(args):
    if args.scale:
        from .bench_scale import run_scale
        try:
            sizes = tuple(int(float(x)) for x in args.sizes.split(","))
        except ValueError:
            raise _input_error(f"--sizes takes triangle counts separated by commas, got {args.sizes!r}") from None
        if not sizes or min(sizes) < 1000:
            raise _input_error(f"--sizes: each count must be at least 1000, got {args.sizes!r}")
        print(json.dumps(run_scale(sizes, folder=args.keep, weave=not args.no_weave), indent=2))
        return 0
    if args.model is None:
        raise _input_error("bench needs a MODEL (or --scale)")
    from .bench import run_bench
    print(json.dumps(run_bench(args.model, repeat=args.repeat, loops=not args.surface_only,
                               refit=not args.no_refit, job=args.job, **_surface_options(args)), indent=2))
    return 0


def cmd_weave(args):
    from .job import weave
    if args.design is None and not args.auto:
        raise _input_error("weave needs --design D.json, --auto, or both")
    result = weave(args.model, design=args.design, auto=args.auto, out=args.out, max_strips=args.max_strips,
                   patches=args.patches, features=not args.no_features, boundary=args.boundary, seed=args.seed,
                   step=args.step, verbose=True, target_triangles=args.target_triangles,
                   feature_angle_deg=args.feature_angle,
                   budget=args.budget, time_limit_s=args.time_limit if args.time_limit > 0 else float("inf"),
                   symmetry=args.symmetry, symmetry_tolerance=args.symmetry_tolerance,
                   crease_pairs=args.crease_pairs)
    report = {k: v for k, v in result.items() if k not in ("surface", "design", "log", "why_red", "why_crease")}
    if args.json:
        print(json.dumps(report))
        return 0
    c = result["regions"]
    irregular = ", ".join(f"{n} of valence {v}" for v, n in result["irregular_vertices"].items()) or "none"
    print(f"{'valid' if result['valid'] else 'NOT valid'} layout: {result['strips']} strips, "
          f"{result['patches']} patches; regions red {c['red']}, crease {c.get('crease', 0)}, orange {c['orange']}, "
          f"yellow {c['yellow']}, "
          f"fine {c['none']}")
    d = result["corner_deviation_deg"]
    print(f"irregular vertices: {irregular}; corner deviation mean {d['mean']:.1f} deg, max {d['max']:.1f} deg"
          + (f" (over the {d['quads']} quads of {d['patches']} patches; {d['mean_all_patches']:.1f} deg with each"
             " patch that is no quad as four corners 90 deg off)" if d.get("quads", 0) < d.get("patches", 0) else ""))
    if "defects" in result:
        from .layout import format_defects
        print(format_defects(result["clean"], result["defects"], result["defect_locations"], result=result))
    for entry in result["log"]:
        print(f"  strip {entry['strip'] + 1}: for the {entry['reason']}"
              f"{'' if entry['region'] < 0 else ' ' + str(entry['region'])} at "
              f"({', '.join(f'{x:.4g}' for x in entry['seed'])})")
    print(f"weaving stopped: {result['stopped']} after {result['work']:g} work units"
          + (f" ({result['cancelled_queries']} loop queries cut by the timeout)" if result["cancelled_queries"] else "")
          + f"; took {result['timings_ms']['total'] / 1000:.1f} s")
    if result.get("why_red"):
        print(f"NOT valid: {result['why_red']}")
    if result.get("why_crease"):
        print(f"NOT crease-conforming: {result['why_crease']}")
    if "fit" in result:
        from .surfacing import format_fit
        print(format_fit(result["fit"]))
    for name, path in result["paths"].items():
        print(f"wrote {path}")
    return 0


def cmd_batch(args):
    from .batch import run_batch
    weave_args = ["--target-triangles", str(args.target_triangles), "--budget", f"{args.budget:g}",
                  "--patches", str(args.patches), "--seed", str(args.seed)]
    if args.max_strips is not None:
        weave_args += ["--max-strips", str(args.max_strips)]
    if args.weave_time_limit is not None:
        weave_args += ["--time-limit", f"{args.weave_time_limit:g}"]
    if args.crease_pairs:
        weave_args += ["--crease-pairs"]
    if args.feature_angle is not None:
        weave_args += ["--feature-angle", f"{args.feature_angle:g}"]
    if args.boundary is not None:
        weave_args += ["--boundary", args.boundary]
    if args.no_features:
        weave_args.append("--no-features")
    try:
        summary = run_batch(args.models, args.out, step=args.step, jobs=args.jobs, time_limit_s=args.time_limit,
                            memory_limit_mb=args.memory_limit, scheduler=args.scheduler, weave_args=weave_args)
    except KeyboardInterrupt:
        print(f"stripweave: interrupted; the running jobs were killed, {args.out}/summary.* hold the models "
              "finished", file=sys.stderr)
        return 130
    from .batch_report import totals
    print(totals(summary["models"]))
    print(f"wrote {args.out}/summary.json, summary.md, index.html")
    return 0


def _add_symmetry_options(p, default, help):
    from .symmetry import SYNTAX
    p.add_argument("--symmetry", default=default, metavar="SPEC", help=f"{help}: {SYNTAX}")
    p.add_argument("--symmetry-tolerance", type=float, default=1e-3, metavar="F",
                   help="largest error of an accepted symmetry, as a fraction of the diagonal (default 1e-3)")


def _input_error(text):
    from ._native import native
    return native.InputError(text)


def _add_design_stage(sub, name, help, output, run):
    """A subcommand that derives one stage of a design: MODEL --design D.json --out DIR."""
    p = sub.add_parser(name, help=help)
    p.add_argument("model")
    p.add_argument("--design", metavar="D.json", required=True, help="the design file")
    p.add_argument("--out", metavar="DIR", required=True, help=f"folder for {output}")
    p.add_argument("--boundary", choices=("aligned", "trimmed"), default=None,
                   help="override the design's boundary mode")
    p.add_argument("--json", action="store_true", help="machine-readable summary")
    _add_surface_options(p)
    p.set_defaults(run=run)


def build_parser():
    from .weave import WeaveOptions   # its defaults are the CLI's
    parser = argparse.ArgumentParser(prog="stripweave", description="Dual Strip Weaving quad layouts")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("info", help="load a model and print its surface report")
    p.add_argument("model")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    _add_symmetry_options(p, "none", "also list the symmetries found (auto) or measure a given one (default none)")
    _add_surface_options(p)
    p.set_defaults(run=cmd_info)

    p = sub.add_parser("loop", help="elastica loops through anchors (paper §5)")
    p.add_argument("model")
    p.add_argument("--anchor", action="append", required=True, metavar="X,Y,Z[,DX,DY,DZ]",
                   help="a point the loop passes, optionally with its tangent; repeat for more, in order")
    p.add_argument("--alternatives", type=int, default=1, help="how many distinct loops to list")
    p.add_argument("--boundary", choices=("aligned", "trimmed"), default=None,
                   help="dual curves meet open boundaries orthogonally (aligned, the default) or at any "
                        "angle (trimmed); with --design, the design's mode unless given")
    p.add_argument("--design", metavar="D.json", help="only loops compatible with this design's strips")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    _add_surface_options(p)
    p.set_defaults(run=cmd_loop)

    _add_design_stage(sub, "strips", "cross field, parameterization and strips of a design (paper §6)",
                      "strips.json", cmd_strips)
    _add_design_stage(sub, "layout", "regions, assessment and primal quad layout of a design (paper §4.2, §7)",
                      "layout.json", cmd_layout)

    p = sub.add_parser("weave", help="the main job: weave a quad layout (automatically) and write "
                                     "design.json, layout.json, report.json, preview.png")
    p.add_argument("model")
    p.add_argument("--design", metavar="D.json", help="start from this design (its strips are kept, first)")
    p.add_argument("--auto", action="store_true", help="complete the design automatically")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for the outputs")
    p.add_argument("--step", action="store_true", help="also fit NURBS patches and write DIR/patches.step")
    p.add_argument("--max-strips", type=int, default=None,
                   help="strips at most, the given ones included (default: 40 beyond the cuts the part's handles "
                        "and holes ask for, two a handle and one a hole beyond the first)")
    p.add_argument("--patches", "--coarseness", type=int, default=0, metavar="N",
                   help="target patch count (default 0: as coarse as the assessment allows)")
    p.add_argument("--no-features", action="store_true", help="do not align the field to sharp features")
    p.add_argument("--boundary", choices=("aligned", "trimmed"), default=None,
                   help="dual curves meet open boundaries orthogonally (aligned) or at any angle (trimmed); "
                        "default: the design's, else aligned")
    p.add_argument("--seed", type=int, default=0, help="vary which seed points are tried first (deterministic)")
    p.add_argument("--budget", type=float, default=WeaveOptions.budget, metavar="UNITS",
                   help="work units of weaving after which only red regions are worked on (deterministic: a "
                        f"loop query is 1, a strip derivation 4; default {WeaveOptions.budget:g})")
    p.add_argument("--time-limit", type=float, default=WeaveOptions.time_limit_s, metavar="S",
                   help="wall-clock safety net: seconds of weaving after which only red regions are worked on "
                        f"(default {WeaveOptions.time_limit_s:g}, not reached on the shared models; 0: none)")
    p.add_argument("--crease-pairs", action="store_true",
                   help="where no single loop parts a crease region (a pocket's or a boss's rim), try pairs of "
                        "crossing loops, after the single loops everywhere (default: off; README)")
    p.add_argument("--json", action="store_true", help="print report.json's content (plus paths) on stdout")
    _add_symmetry_options(p, None, "weave symmetrically, every added strip with its images (default: the "
                                   "design's symmetry, else none)")
    _add_surface_options(p)
    p.set_defaults(run=cmd_weave)

    p = sub.add_parser("batch", help="weave every model of files and folders, one process per model, and "
                                     "write OUT/summary.json, summary.md and index.html")
    p.add_argument("models", nargs="+", metavar="MODEL_OR_DIR",
                   help="model files, and folders searched recursively for model files")
    p.add_argument("--out", metavar="OUT", required=True, help="folder for OUT/<model>/ and the summaries")
    p.add_argument("--step", action="store_true", help="also fit NURBS patches (patches.step, deviation.png)")
    p.add_argument("--jobs", type=int, default=1, metavar="N",
                   help="models woven at once on this machine (default 1: each model's time and memory are "
                        "then those of one job alone, comparable with `bench`; use the core count for speed)")
    p.add_argument("--time-limit", type=float, default=600.0, metavar="S",
                   help="seconds per model, after which its processes are killed: status timeout "
                        "(default 600; 0: none)")
    p.add_argument("--memory-limit", type=float, default=0.0, metavar="MB",
                   help="resident memory per model (its process tree), above which it is killed: status error "
                        "(default 0: none)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run the jobs on the Dask distributed cluster at ADDRESS (e.g. tcp://host:8786; its "
                        "workers must see the same paths) instead of locally")
    p.add_argument("--weave-time-limit", type=float, default=None, metavar="S",
                   help="weave's --time-limit (its wall-clock safety net for weaving)")
    p.add_argument("--budget", type=float, default=WeaveOptions.budget, metavar="UNITS", help="weave's --budget")
    p.add_argument("--crease-pairs", action="store_true", help="weave's --crease-pairs")
    p.add_argument("--max-strips", type=int, default=None, help="weave's --max-strips")
    p.add_argument("--patches", type=int, default=0, metavar="N", help="weave's --patches")
    p.add_argument("--no-features", action="store_true", help="weave's --no-features")
    p.add_argument("--boundary", choices=("aligned", "trimmed"), default=None, help="weave's --boundary")
    p.add_argument("--seed", type=int, default=0, help="weave's --seed")
    p.add_argument("--target-triangles", type=int, default=30000, help="size of the solver mesh (weave's)")
    p.add_argument("--feature-angle", type=float, default=None, help="weave's --feature-angle")
    p.set_defaults(run=cmd_batch)

    p = sub.add_parser("bench", help="time every pipeline stage (JSON)")
    p.add_argument("model", nargs="?")
    p.add_argument("--scale", action="store_true",
                   help="no MODEL: a generated bumpy torus at --sizes triangles (ingest, proxy, hover, weave, "
                        "peak memory against a numpy read)")
    p.add_argument("--sizes", default="100000,1000000,5000000", help="--scale's triangle counts")
    p.add_argument("--keep", default=None, metavar="DIR", help="--scale: keep the generated STL files here")
    p.add_argument("--no-weave", action="store_true", help="--scale: skip weave --auto")
    p.add_argument("--repeat", type=int, default=3, help="runs per stage (median and p95 are reported)")
    p.add_argument("--json", action="store_true", help="accepted for symmetry: bench always prints JSON")
    p.add_argument("--surface-only", action="store_true", help="time the surface stage alone")
    p.add_argument("--no-refit", action="store_true", help="skip the surfacing stage (refit_s)")
    p.add_argument("--job", action="store_true",
                   help="also the main job's memory per stage: weave MODEL --auto --step in a child process "
                        "(job.stages, job.peak; job.imports: Python with the job's imports alone, OCCT's included; "
                        "job.freecad_imports: and FreeCAD's Part)")
    _add_surface_options(p)
    p.set_defaults(run=cmd_bench)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    from ._native import native
    from .files import check_out_dir
    try:
        limit = getattr(args, "memory_guard_mb", None)   # batch's --memory-limit is its own (a kill limit)
        if limit is not None:
            if not limit > 0 or limit == float("inf"):
                raise native.InputError(f"--memory-limit must be a positive number of MB, got {limit:g}")
            # The native guard (core/memory_guard.h) reads it at every stage; batch's runs inherit it.
            os.environ["STRIPWEAVE_MEMORY_LIMIT_MB"] = f"{limit:g}"
        if getattr(args, "out", None) is not None:
            check_out_dir(args.out)   # before the work: an unusable folder is found at once
        return args.run(args)
    except native.InputError as exc:
        print(f"stripweave: error: {exc}", file=sys.stderr)
    except native.Cancelled:
        print("stripweave: cancelled", file=sys.stderr)
    except OSError as exc:
        print(f"stripweave: error: {exc}", file=sys.stderr)
    except (RecursionError, MemoryError, UnicodeError, TypeError, ValueError, ArithmeticError) as exc:
        # No traceback reaches a user; STRIPWEAVE_TRACEBACK=1 shows it (for a bug report).
        if os.environ.get("STRIPWEAVE_TRACEBACK"):
            raise
        print(f"stripweave: error: {type(exc).__name__}: {exc}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
