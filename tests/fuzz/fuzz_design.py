"""A mutation fuzzer for the design parser (Design.load: JSON, UTF-8, the format's checks).

libFuzzer cannot drive Python and Debian has no atheris, so this is a small deterministic
mutation loop in the same spirit: start from the seed corpus (tests/fuzz/corpus/design),
mutate bytes (flip, insert, delete, duplicate a run, splice a JSON token from a dictionary),
load each result. Every input must load or raise InputError; anything else (another
exception, a hang past --timeout) is a finding, saved under --findings and counted.

    /usr/bin/python3 tests/fuzz/fuzz_design.py --seconds 60 [--seed 1] [--findings DIR]
"""
import argparse
import os
import random
import signal
import sys
import tempfile
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = ["/usr/lib/freecad-python3/lib", os.path.join(REPO, "workbench"),
                os.environ.get("STRIPWEAVE_BUILD", os.path.join(REPO, "build"))]

import stripweave as sw                      # noqa: E402
from stripweave.design import Design         # noqa: E402

TOKENS = [b"null", b"true", b"false", b"NaN", b"Infinity", b"-Infinity", b"1e400", b"-0", b"[]", b"{}",
          b'"point"', b'"direction"', b'"anchors"', b'"strips"', b'"options"', b'"k"', b'"version"',
          b"9" * 40, b"[" * 50, b"\xff", b"\xc3\x28", b'"\\ud800"', b"0.5", b"4", b"1e308"]


def mutate(data, rng):
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(5)
        at = rng.randrange(len(data) + 1)
        if kind == 0 and data:
            data[min(at, len(data) - 1)] ^= 1 << rng.randrange(8)
        elif kind == 1:
            data[at:at] = bytes([rng.randrange(256)])
        elif kind == 2 and data:
            del data[at:at + rng.randint(1, 8)]
        elif kind == 3 and data:
            run = data[at:at + rng.randint(1, 32)]
            data[at:at] = run * rng.randint(1, 4)
        else:
            data[at:at] = rng.choice(TOKENS)
    return bytes(data)


class Hang(Exception):
    pass


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=10, help="seconds one input may take")
    ap.add_argument("--findings", default=os.path.join(tempfile.gettempdir(), "stripweave-fuzz-design"))
    args = ap.parse_args()
    rng = random.Random(args.seed)
    corpus_dir = os.path.join(HERE, "corpus", "design")
    corpus = [open(os.path.join(corpus_dir, f), "rb").read() for f in sorted(os.listdir(corpus_dir))]
    os.makedirs(args.findings, exist_ok=True)
    path = os.path.join(tempfile.mkdtemp(), "design.json")

    def on_alarm(*_):
        raise Hang()
    signal.signal(signal.SIGALRM, on_alarm)
    runs = refused = loaded = findings = 0
    end = time.monotonic() + args.seconds
    while time.monotonic() < end:
        data = mutate(rng.choice(corpus), rng)
        with open(path, "wb") as f:
            f.write(data)
        runs += 1
        signal.setitimer(signal.ITIMER_REAL, args.timeout)
        try:
            Design.load(path)
            loaded += 1
            if rng.random() < 0.05:
                corpus.append(data)   # keep some valid variants: mutate deeper from them
        except sw.InputError:
            refused += 1
        except BaseException as exc:  # noqa: BLE001 (any other outcome is a finding)
            if isinstance(exc, KeyboardInterrupt):
                raise
            findings += 1
            name = os.path.join(args.findings, f"finding-{findings}.json")
            with open(name, "wb") as f:
                f.write(data)
            print(f"finding {findings}: {type(exc).__name__}: {exc} -> {name}", file=sys.stderr)
            if not isinstance(exc, Hang):
                traceback.print_exc(limit=3)
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
    print(f"design fuzzer: {runs} inputs in {args.seconds:g} s, {loaded} loaded, {refused} refused "
          f"(InputError), corpus {len(corpus)}, {findings} findings")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
