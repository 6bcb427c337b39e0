"""The `stripweave` command line (run it as build/stripweave).

    stripweave info MODEL [--json]       the surface report
    stripweave loop MODEL --anchor X,Y,Z[,DX,DY,DZ] [--anchor ...] [--alternatives K]
                    [--boundary aligned|trimmed] [--json]   elastica loops through anchors
    stripweave bench MODEL [--repeat N]  stage timings and sizes, JSON

MODEL is STEP/STP, IGES/IGS, BREP/BRP, STL, OBJ, OFF, PLY, or an FCStd with
one shape or mesh. Bad input ends with a one-line error and exit status 1.
"""
import argparse
import json
import sys


def _add_surface_options(p):
    g = p.add_argument_group("surface options")
    g.add_argument("--target-triangles", type=int, default=30000,
                   help="size of the solver mesh (0 keeps the tessellation or input mesh)")
    g.add_argument("--feature-angle", type=float, default=30.0,
                   help="dihedral angle in degrees above which an edge is a sharp feature")
    g.add_argument("--deflection", type=float, default=0.0,
                   help="B-rep chordal deflection in model units (default: 1e-3 of the diagonal)")


def _surface_options(args):
    return {"target_triangles": args.target_triangles, "feature_angle_deg": args.feature_angle,
            "deflection": args.deflection}


def cmd_info(args):
    from .report import format_report, info_dict
    from .surface import load
    surface = load(args.model, **_surface_options(args))
    info = info_dict(surface)
    if args.json:
        print(json.dumps(info, indent=2))
    else:
        print(format_report(info))
    return 0


def cmd_loop(args):
    from .loops import LoopSession, parse_anchor, timed
    from .surface import load
    anchors = [parse_anchor(a) for a in args.anchor]
    surface = load(args.model, **_surface_options(args))
    session = LoopSession(surface, boundary=args.boundary)
    loops, ms = timed(session.loops, anchors, alternatives=args.alternatives)
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
        print(f"search took {ms:.1f} ms (graph built in {session.stats()['graph_build_s']:.2f} s)")
    return 0


def cmd_bench(args):
    from .bench import run_bench
    print(json.dumps(run_bench(args.model, repeat=args.repeat, loops=not args.surface_only,
                               **_surface_options(args)), indent=2))
    return 0


def build_parser():
    parser = argparse.ArgumentParser(prog="stripweave", description="Dual Strip Weaving quad layouts")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("info", help="load a model and print its surface report")
    p.add_argument("model")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    _add_surface_options(p)
    p.set_defaults(run=cmd_info)

    p = sub.add_parser("loop", help="elastica loops through anchors (paper §5)")
    p.add_argument("model")
    p.add_argument("--anchor", action="append", required=True, metavar="X,Y,Z[,DX,DY,DZ]",
                   help="a point the loop passes, optionally with its tangent; repeat for more, in order")
    p.add_argument("--alternatives", type=int, default=1, help="how many distinct loops to list")
    p.add_argument("--boundary", choices=("aligned", "trimmed"), default="aligned",
                   help="dual curves meet open boundaries orthogonally (aligned) or at any angle (trimmed)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    _add_surface_options(p)
    p.set_defaults(run=cmd_loop)

    p = sub.add_parser("bench", help="time every pipeline stage (JSON)")
    p.add_argument("model")
    p.add_argument("--repeat", type=int, default=3, help="runs per stage (median and p95 are reported)")
    p.add_argument("--json", action="store_true", help="accepted for symmetry: bench always prints JSON")
    p.add_argument("--surface-only", action="store_true", help="time the surface stage alone")
    _add_surface_options(p)
    p.set_defaults(run=cmd_bench)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    from ._native import native
    try:
        return args.run(args)
    except native.InputError as exc:
        print(f"stripweave: error: {exc}", file=sys.stderr)
    except native.Cancelled:
        print("stripweave: cancelled", file=sys.stderr)
    except OSError as exc:
        print(f"stripweave: error: {exc}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
