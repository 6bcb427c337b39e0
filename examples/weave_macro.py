"""A FreeCAD macro: weave a quad layout on a part automatically and print the report.

    freecadcmd examples/weave_macro.py            (or Macro > Macros... in the FreeCAD GUI)

It makes the example handle (examples/make_example_part.py), weaves a layout on it with
stripweave.weave() and prints the figures of report.json. Outputs go to ./woven-handle/.
To weave your own part, replace `shape` by e.g. Part.read("part.step") or
App.ActiveDocument.ActiveObject.Shape. StripWeave must be built (build/) or installed as
a workbench: the lines below find the repository's copy when run from it.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals() else os.getcwd()
REPO = os.path.dirname(HERE)
for path in (os.path.join(REPO, "workbench"), os.path.join(REPO, "build"), HERE):
    if path not in sys.path:
        sys.path.append(path)

import stripweave as sw  # noqa: E402
from make_example_part import make_handle  # noqa: E402

shape = make_handle()
report = sw.weave(shape, out=os.path.join(os.getcwd(), "woven-handle"), max_strips=30)

print(f"valid: {report['valid']}, strips: {report['strips']}, patches: {report['patches']}")
print(f"regions: {report['regions']}")
print(f"irregular vertices: {report['irregular_vertices']}")
print(f"corner deviation: mean {report['corner_deviation_deg']['mean']:.1f} deg, "
      f"max {report['corner_deviation_deg']['max']:.1f} deg")
for entry in report["log"]:
    print(f"  strip {entry['strip'] + 1} for the {entry['reason']} at {[round(x, 2) for x in entry['seed']]}")
for name, path in report["paths"].items():
    print(f"{name}: {path}")
