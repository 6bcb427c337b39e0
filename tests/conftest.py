"""Test setup: FreeCAD's modules, the workbench package and the build on sys.path.
No outside data is used: every model is generated (see models.py)."""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.environ.get("STRIPWEAVE_BUILD", os.path.join(REPO, "build"))
FREECAD_LIB = "/usr/lib/freecad-python3/lib"
for path in (FREECAD_LIB, os.path.join(REPO, "workbench"), BUILD, os.path.dirname(os.path.abspath(__file__))):
    if path not in sys.path:
        sys.path.append(path)
