"""StripWeave workbench for FreeCAD (namespace package ``freecad.stripweave_wb``).

FreeCAD finds this package through ``Mod/StripWeave -> <repo>/workbench``
(see ``workbench/link_into_freecad.sh``) and imports ``init_gui`` when the GUI
starts.  This module only works out where things are and makes the
``stripweave`` Python package and its native extension ``_stripweave``
importable; it computes nothing.

Repository layout assumed (all paths derived from the *real* path of this
file, so a symlinked Mod folder works)::

    <repo>/workbench/freecad/stripweave_wb/   this package
    <repo>/workbench/stripweave/              the Python API over the native library
    <repo>/build/_stripweave*.so              the native extension (CMake build)
    <repo>/resources/icons/*.svg              icons

``STRIPWEAVE_BUILD`` (as for the ``stripweave`` package) or
``STRIPWEAVE_BUILD_DIR`` overrides the build directory.
"""

import importlib.util
import os
import sys

__version__ = "0.1.0"

PACKAGE_DIR = os.path.dirname(os.path.realpath(__file__))
WORKBENCH_DIR = os.path.dirname(os.path.dirname(PACKAGE_DIR))
REPO_ROOT = os.path.dirname(WORKBENCH_DIR)
RESOURCES_DIR = os.path.join(REPO_ROOT, "resources")
ICON_DIR = os.path.join(RESOURCES_DIR, "icons")

WORKBENCH_ICON = os.path.join(ICON_DIR, "StripWeave.svg")


def icon_path(name):
    """Absolute path of an icon in resources/icons (``name`` with extension)."""
    return os.path.join(ICON_DIR, name)


def build_dir():
    """Directory that holds the native extension ``_stripweave``."""
    return (os.environ.get("STRIPWEAVE_BUILD") or os.environ.get("STRIPWEAVE_BUILD_DIR")
            or os.path.join(REPO_ROOT, "build"))


def ensure_import_path():
    """Make ``import stripweave`` and ``import _stripweave`` work.

    Adds ``<repo>/workbench`` (for the ``stripweave`` package) and the build
    directory (for ``_stripweave``) to ``sys.path`` when they are needed and
    not there yet.  Safe to call any number of times.
    """
    if WORKBENCH_DIR not in sys.path and importlib.util.find_spec("stripweave") is None:
        sys.path.append(WORKBENCH_DIR)
    if importlib.util.find_spec("_stripweave") is None:
        bdir = build_dir()
        if os.path.isdir(bdir) and bdir not in sys.path:
            sys.path.append(bdir)


ensure_import_path()


def import_stripweave():
    """Import and return the ``stripweave`` package.

    Raises ``ImportError`` with a message that says what to do when the
    native library has not been built.
    """
    ensure_import_path()
    try:
        import stripweave  # noqa: F401  (the package we are a GUI for)
    except ImportError as exc:
        hint = "" if "cmake" in str(exc) else (
            " Build the native library first (cmake -S {0} -B {1} && cmake --build {1}), or set "
            "STRIPWEAVE_BUILD to the directory holding _stripweave*.so.".format(REPO_ROOT, build_dir()))
        raise ImportError("StripWeave: cannot import the stripweave package: {}.{}".format(
            str(exc).rstrip("."), hint)) from exc
    return stripweave
