"""Locate and import the native module `_stripweave`.

The build puts it in `<repo>/build`. It is imported from `sys.path` if it is
already there (the `stripweave` launcher, an installed copy), else from
`$STRIPWEAVE_BUILD`, else from the build folder next to this package.
"""
import importlib
import os
import sys


def _import_native():
    try:
        return importlib.import_module("_stripweave")
    except ImportError:
        pass
    here = os.path.dirname(os.path.realpath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    for folder in (os.environ.get("STRIPWEAVE_BUILD"), os.path.join(repo, "build")):
        if not folder or not os.path.isdir(folder):
            continue
        if folder not in sys.path:
            sys.path.append(folder)
        try:
            return importlib.import_module("_stripweave")
        except ImportError:
            continue
    raise ImportError(
        "StripWeave's native module _stripweave is not built for this Python "
        f"({sys.executable}); build it with `cmake -S {repo} -B {repo}/build && cmake --build {repo}/build` "
        "(see README.md), or set STRIPWEAVE_BUILD to the folder that holds it")


native = _import_native()
