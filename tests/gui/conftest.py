# run_gui_test.py matches pytest's "*_test.py" pattern but is a script for
# FreeCAD's GUI (it needs FreeCADGui), not a pytest module: test_gui.py runs it.
collect_ignore = ["run_gui_test.py"]
