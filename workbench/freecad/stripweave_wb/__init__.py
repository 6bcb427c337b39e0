"""StripWeave workbench for FreeCAD (namespace package ``freecad.stripweave_wb``).

FreeCAD finds this package through ``Mod/StripWeave -> <repo>`` (the Addon
Manager's clone, or ``workbench/link_into_freecad.sh``): <repo>/package.xml
names ``workbench/`` as the workbench's subdirectory, which FreeCAD puts on
``sys.path``; it imports ``init_gui`` when the GUI starts.  This module only works out where things are and makes the
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

The main job as macro functions (GUI or ``freecadcmd``; blocking)::

    import freecad.stripweave_wb as wb
    from freecad.stripweave_wb import layout_model, patches_model
    wb.auto_weave(design, max_strips=20)            # weave_job.run
    layout = layout_model.create(design)
    patches = patches_model.create(layout, tolerance=None)
    wb.export_step(patches, "out.step")             # patches_model.export_step
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
        raise ImportError("StripWeave: cannot import the stripweave package: {}. {}".format(
            str(exc).rstrip("."), setup_hint())) from exc
    return stripweave


def setup_hint():
    """What to run when the native library is missing (the Addon Manager
    installs the Python files only: it cannot build C++)."""
    return ("The native library is not built: run  bash {}  in a terminal (it installs the Debian "
            "packages it needs and builds {}/_stripweave*.so; root or sudo for apt-get), then restart "
            "FreeCAD. Or set STRIPWEAVE_BUILD to a folder holding _stripweave*.so.".format(
                os.path.join(REPO_ROOT, ".ci", "setup"), build_dir()))


# -- the main job as macro functions (headless: blocking; lazy imports) ------------------

def auto_weave(design, **options):
    """Complete a Design by automatic weaving, keeping its strips (one
    transaction "Auto weave"); options as stripweave.weave.WeaveOptions.
    Returns the WeaveResult (log, stopped, assessment, work)."""
    from . import weave_job
    return weave_job.run(design, **options)


def export_step(patches, path):
    """Write a Patches object (Fit patches) as STEP and read it back:
    {"path", "faces", "faces_read_back", "valid", "solids", "shells"}."""
    from . import patches_model
    return patches_model.export_step(patches, path)
