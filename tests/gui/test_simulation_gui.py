"""GUI test under xvfb-run (freecad script): seeing the result and the pose simulation on a
30 x 20 x 12 mm box layered flat from its bottom face (the positioner
angles stay constant over a layer: what moves is the torch along the path).

- After a run from the GUI the solid is hidden, the layers and paths are shown and the cell is
  hidden, so Fit All frames the part; the cell toggle shows and hides the positioner, robot,
  torch and deposit.
- The layer inspector isolates exactly one layer: its surface and its paths (same layer number
  and height), nothing else of the Job; the dialog names the layer, its height, its coverage or
  that none was measured, and its warnings.
- The simulation player: scrubbing to a weld point puts the torch tip on the motion point's TCP
  (the part-frame point carried by the shown part's placement, and the motion's tool_in_world),
  the torch axis along the tool z; the robot's forward kinematics of the point's joints reach
  the same TCP; the deposit count grows with the point; the torch moves along a path while the
  positioner angles stay put; play advances, pause stops and records the point.
Screenshots go to the test's folder under the build tree."""

import os
import sys

import FreeCAD
import FreeCADGui
from PySide import QtGui

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))
from gui_testing import TMP, check, finish, process_events, report_view  # noqa: E402


def visible_objects(doc):
    return [o for o in doc.Objects if o.ViewObject is not None and o.ViewObject.Visibility
            and hasattr(o, "Shape") and not o.Shape.isNull()]


def render_svg(path, name):
    """Renders an SVG icon to TMP/<name>.png as FreeCAD does (QSvgRenderer; a QIcon needs Qt's
    SVG image plugin, which a minimal Qt 6 install lacks); False if it is not valid SVG."""
    from PySide import QtSvg

    renderer = QtSvg.QSvgRenderer(path)
    if not renderer.isValid():
        return False
    image = QtGui.QImage(64, 64, QtGui.QImage.Format_ARGB32)
    image.fill(QtGui.QColor("white"))
    painter = QtGui.QPainter(image)
    renderer.render(painter)
    painter.end()
    return image.save(os.path.join(TMP, name + ".png"))


def grab(widget, name):
    """A dialog as TMP/<name>.png (the main window's grab does not hold top-level dialogs)."""
    path = os.path.join(TMP, name + ".png")
    widget.grab().save(path)
    print("screenshot: %s" % path, flush=True)


def save_view(name):
    view = FreeCADGui.ActiveDocument.ActiveView
    path = os.path.join(TMP, name + ".png")
    view.saveImage(path, 800, 600, "White")
    print("screenshot: %s" % path, flush=True)
    return path


def check_results_shown(job, box):
    from freecad.curvedslicer import api
    from freecad.curvedslicer.stages import poses

    check(not box.ViewObject.Visibility, "after the run the solid is hidden")
    check(all(o.ViewObject.Visibility for o in api.layers(job) + api.path_features(job)),
          "after the run every layer surface and path is shown")
    cell = poses.pose_objects(job)
    check(set(cell) >= {"PositionerBase", "PositionerTable", "PosePart", "Torch", "Robot",
                        "Deposit"}, "the cell has positioner, part, torch, robot and deposit "
          "(%s)" % sorted(cell))
    check(not any(o.ViewObject.Visibility for o in cell.values()), "after the run the cell is "
          "hidden")
    box_of = FreeCAD.BoundBox()
    for o in visible_objects(job.Document):
        box_of.add(o.Shape.BoundBox)
    check(box_of.DiagonalLength < 1.5 * box.Shape.BoundBox.DiagonalLength,
          "what is shown is the part's size (%.1f mm), so Fit All frames it"
          % box_of.DiagonalLength)
    save_view("results_after_run")
    box.ViewObject.Visibility = True
    api.show_solid(job, False)
    check(not box.ViewObject.Visibility, "show_solid(job, False) hides the solid again")
    api.show_solid(job, True)
    check(box.ViewObject.Visibility, "show_solid restores the solid")
    api.show_solid(job, False)

    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(job.Document.Name, job.Name)
    FreeCADGui.runCommand("CurvedSlicer_ToggleCell")
    process_events()
    check(all(o.ViewObject.Visibility for o in poses.pose_objects(job).values()),
          "the cell toggle shows the cell")
    check(not any(o.ViewObject.Visibility for o in api.layers(job) + api.path_features(job)),
          "with the cell shown the layers and paths at the part's own frame are hidden")
    FreeCADGui.runCommand("CurvedSlicer_ToggleCell")
    process_events()
    check(not any(o.ViewObject.Visibility for o in poses.pose_objects(job).values()),
          "the cell toggle hides it again")
    check(all(o.ViewObject.Visibility for o in api.layers(job) + api.path_features(job)),
          "with the cell hidden every layer and path is shown again")


def check_layer_inspector(job):
    from freecad.curvedslicer import api
    from freecad.curvedslicer.stages import paths as path_stage
    from freecad.curvedslicer.taskpanels.layer_dialog import LayerDialog, coverage_lines

    count = job.PlanLayerCount
    check(count >= 3, "the plan has layers to inspect (%d)" % count)
    dialog = LayerDialog(job, FreeCADGui.getMainWindow())
    dialog.show()
    for index, widget in ((2, dialog.spin), (3, dialog.slider)):
        widget.setValue(index)
        process_events()
        surfaces = [o for o in api.layers(job) if o.ViewObject.Visibility]
        paths = [o for o in api.path_features(job) if o.ViewObject.Visibility]
        travel = path_stage.travel_object(job)
        check(len(surfaces) == 1 and len(paths) == 1, "layer %d: exactly one layer surface (%d) "
              "and one path feature (%d) shown" % (index, len(surfaces), len(paths)))
        if surfaces and paths:
            check(surfaces[0].LayerIndex == index and paths[0].LayerIndex == index
                  and abs(float(surfaces[0].Height) - float(paths[0].Height)) < 1e-6,
                  "layer %d: the surface and the paths shown are that layer's (heights %.3f, "
                  "%.3f mm)" % (index, float(surfaces[0].Height), float(paths[0].Height)))
        check(not travel.ViewObject.Visibility, "layer %d: the travel is hidden" % index)
        check(dialog.spin.value() == index and dialog.slider.value() == index,
              "spin box and slider agree on layer %d" % index)
        info = api.layer_info(job, index)
        title = dialog.title.text()
        check(("Layer %d of %d" % (index, count)) in title and ("%.2f mm" % info["height"]) in
              title, "the dialog names the layer and its height: %r" % title)
        coverage = dialog.coverage.text()
        expected = coverage_lines(info["coverage"])
        check(coverage.startswith("Coverage: ") and (
            all(line in coverage for line in expected) if expected else "not measured" in
            coverage), "the dialog shows the layer's coverage: %r" % coverage)
        warnings = dialog.warnings.toPlainText()
        check(all(w in warnings for w in info["warnings"]) and warnings,
              "the dialog shows the layer's warnings: %r" % warnings[:120])
        FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
        FreeCADGui.SendMsgToActiveView("ViewFit")
        process_events()
        save_view("layer_%d" % index)
    grab(dialog, "layer_dialog")
    check_void_markers(job, dialog)
    dialog.all_layers.setChecked(True)
    process_events()
    check(all(o.ViewObject.Visibility for o in api.layers(job) + api.path_features(job)),
          "All layers shows every layer again")
    dialog.voids.setChecked(True)
    process_events()
    markers = api.void_markers(job)
    check(all(m.ViewObject.Visibility for m in markers), "with all layers shown, every layer's "
          "uncovered regions are shown (%d marker features)" % len(markers))
    dialog.voids.setChecked(False)
    process_events()
    dialog.close()
    lines = coverage_lines({"measured": True, "area_mm2": 600.0, "void_share": 0.0125,
                            "overlap_share": 0.25, "arc_starts": 3, "voids": [{}, {}]})
    check(lines == ["area mm2: 600", "void share: 1.2 %", "overlap share: 25.0 %",
                    "arc starts: 3", "voids: 2"], "coverage lines of a measured layer: %s"
          % lines)
    check(coverage_lines({"measured": False, "void_share": 0.0}) == [],
          "an unmeasured layer has no coverage lines")


def check_void_markers(job, dialog):
    """The Inspect dialog's "Uncovered regions": the shown layer's void discs in red, as many as
    the plan lists for it; unchecked, none."""
    from freecad.curvedslicer import api
    from freecad.curvedslicer.viewproviders.view_job import VOID_COLOR

    index = dialog.spin.value()
    listed = len((api.layer_info(job, index)["coverage"] or {}).get("voids", []))
    dialog.voids.setChecked(True)
    process_events()
    shown = [m for m in api.void_markers(job) if m.ViewObject.Visibility]
    check(sum(len(m.Shape.Faces) for m in shown) == listed and
          all(m.LayerIndex == index for m in shown),
          "layer %d: its %d voids shown as discs (%d)" % (index, listed,
                                                         sum(len(m.Shape.Faces) for m in shown)))
    check(all(max(abs(a - b) for a, b in zip(m.ViewObject.ShapeColor[:3], VOID_COLOR)) < 0.01
              for m in shown), "the discs are red")
    dialog.voids.setChecked(False)
    process_events()
    check(not any(m.ViewObject.Visibility for m in api.void_markers(job)),
          "unchecked, no uncovered region is shown")


def torch_tip_and_axis(job):
    from freecad.curvedslicer.stages import poses

    torch = poses.pose_objects(job)["Torch"]
    return torch.Placement.Base, torch.Placement.Rotation.multVec(FreeCAD.Vector(0, 0, 1))


def part_point_in_world(job, motion, index):
    """The motion point's part-frame position carried by the shown part's placement."""
    from freecad.curvedslicer.stages import poses

    part = poses.pose_objects(job)["PosePart"]
    return part.Placement.multVec(FreeCAD.Vector(*motion["position"][index].tolist()))


def check_scrub(job, dialog, motion, index):
    from freecad.curvedslicer.core import native
    from freecad.curvedslicer.stages import poses

    dialog.slider.setValue(index)
    process_events()
    check(job.PosePoint == index and dialog.spin.value() == index,
          "scrubbing to point %d shows it (PosePoint %d)" % (index, job.PosePoint))
    tip, axis = torch_tip_and_axis(job)
    tcp = FreeCAD.Matrix(*[float(v) for row in motion["tool_in_world"][index] for v in row])
    check((tip - part_point_in_world(job, motion, index)).Length < 1e-6,
          "point %d: the torch tip is on the motion point carried by the part (%.2e mm)"
          % (index, (tip - part_point_in_world(job, motion, index)).Length))
    check((tip - tcp.multiply(FreeCAD.Vector(0, 0, 0))).Length < 1e-9,
          "point %d: the torch tip is the motion's TCP" % index)
    tool_z = FreeCAD.Vector(tcp.A13, tcp.A23, tcp.A33)
    check(axis.getAngle(tool_z) < 1e-9 and axis.getAngle(FreeCAD.Vector(0, 0, -1)) < 1e-6,
          "point %d: the torch axis is the tool z, along gravity" % index)
    arm = native.robot_arm_points(motion["cell_json"], motion["joints"][index].tolist())
    reach = FreeCAD.Matrix(*[float(v) for row in arm["tcp"] for v in row]).multiply(
        FreeCAD.Vector(0, 0, 0))
    check((reach - tip).Length < 1e-3, "point %d: the robot's joints reach the torch tip "
          "(%.2e mm)" % (index, (reach - tip).Length))
    robot = poses.pose_objects(job)["Robot"]
    check(robot.Shape.BoundBox.isInside(FreeCAD.Vector(*arm["elbow"])), "point %d: the robot "
          "model passes through its elbow" % index)
    deposit = poses.pose_objects(job)["Deposit"]
    expected = int(motion["arc_on"][:index + 1].sum())
    check(deposit.DepositMoves == expected, "point %d: deposit of %d welded moves (%d)"
          % (index, expected, deposit.DepositMoves))
    label, flags = dialog.robot_label.text(), dialog.flags_label.text()
    info = dialog.show_point(index)
    check(all(("%.1f°" % j) in label for j in info["joints"]) and
          all(c in label for c in info["configuration"]), "point %d: the dialog shows the "
          "joints and the configuration: %r" % (index, label))
    check(flags == (", ".join(info["flags"]) or "none"), "point %d: the dialog shows the "
          "motion flags: %r" % (index, flags))
    positioner = dialog.positioner_label.text()
    check(("a1 %.1f°" % info["a1"]) in positioner and ("a2 %.1f°" % info["a2"]) in positioner,
          "point %d: the dialog shows the positioner angles: %r" % (index, positioner))
    return tip, deposit.DepositMoves, len(deposit.Shape.Edges)


def check_simulation(job):
    from freecad.curvedslicer import api
    from freecad.curvedslicer.stages import poses
    from freecad.curvedslicer.taskpanels.simulation_dialog import SPEEDS, SimulationDialog

    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(job.Document.Name, job.Name)
    from freecad.curvedslicer.commands import job_commands

    check(job_commands.Simulate().IsActive(), "Simulate is enabled for a planned Job")
    api.show_cell(job, True)
    motion = api.motion(job)
    dialog = SimulationDialog(job, FreeCADGui.getMainWindow())
    dialog.show()
    count = len(motion["a1"])
    kinds = motion["kind"]
    span = max(motion["paths"], key=lambda s: s["end"] - s["begin"])
    welds = [i for i in range(span["begin"], span["end"]) if bool(motion["arc_on"][i])]
    check(len(welds) >= 4, "the longest path has welded points (%d)" % len(welds))
    scrubbed = [check_scrub(job, dialog, motion, i) + (job.PoseA1, job.PoseA2)
                for i in (welds[1], welds[len(welds) // 3], welds[2 * len(welds) // 3],
                          welds[-2])]
    for (tip1, deposited1, edges1, _, _), (tip2, deposited2, edges2, _, _) in zip(
            scrubbed, scrubbed[1:]):
        check(deposited2 > deposited1 and edges2 > edges1, "the deposit grows along the path "
              "(%d -> %d moves, %d -> %d edges)" % (deposited1, deposited2, edges1, edges2))
    tips = [s[0] for s in scrubbed]
    spread = max((a - b).Length for a in tips for b in tips)
    check(spread > 10.0, "the torch moves along the path (points up to %.1f mm apart)" % spread)
    angles = {(round(s[3], 6), round(s[4], 6)) for s in scrubbed}
    check(len(angles) == 1, "flat layers: the positioner angles stay put along the path (%s)"
          % sorted(angles))
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    process_events()
    save_view("simulation_cell")
    # Closer: the positioner, the part, the torch and the deposit (the robot hidden).
    poses.pose_objects(job)["Robot"].ViewObject.Visibility = False
    view.fitAll()
    process_events()
    save_view("simulation_torch")
    poses.pose_objects(job)["Robot"].ViewObject.Visibility = True

    # Play: the point advances; pause stops and records it.
    dialog.slider.setValue(0)
    # 10× real time: it advances within the second but does not reach the end (at 200× a fast
    # machine played the whole plan before Pause was clicked)
    dialog.speed.setCurrentIndex(SPEEDS.index(10.0))
    start = job.PosePoint
    dialog.play_button.click()
    check(dialog.is_playing() and dialog.play_button.text() == "Pause", "Play starts playback")
    process_events(1.0)
    moved = job.PosePoint
    dialog.play_button.click()
    check(not dialog.is_playing() and dialog.play_button.text() == "Play", "Pause stops it")
    check(moved > start, "playing advanced the point (%d -> %d)" % (start, moved))
    stopped = job.PosePoint
    process_events(0.3)
    check(job.PosePoint == stopped, "paused: the point stays at %d" % stopped)
    grab(dialog, "simulation_dialog")
    dialog.slider.setValue(count - 1)
    process_events()
    last = poses.pose_objects(job)["Deposit"].DepositMoves
    check(last == int(motion["arc_on"].sum()), "at the last point the whole plan is deposited "
          "(%d welded moves)" % last)
    check(int(kinds[count - 1]) == 4 or job.PosePoint == count - 1, "the last point is shown")
    dialog.close()


def run():
    FreeCADGui.showMainWindow() if hasattr(FreeCADGui, "showMainWindow") else None
    FreeCADGui.activateWorkbench("CurvedSlicerWorkbench")
    from freecad.curvedslicer import api
    from freecad.curvedslicer.commands import job_commands

    for name in ("CurvedSlicer_InspectLayers", "CurvedSlicer_ToggleCell",
                 "CurvedSlicer_ToggleVoids", "CurvedSlicer_Simulate"):
        check(name in FreeCADGui.listCommands(), "command %s exists" % name)
        pixmap = job_commands.COMMANDS[name]().GetResources()["Pixmap"]
        check(os.path.isfile(pixmap) and render_svg(pixmap, "icon_%s" % name),
              "command %s has its icon %s" % (name, os.path.basename(pixmap)))
    doc = FreeCAD.newDocument("SimulationTest")
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 30, 20, 12
    box.Placement.Base = FreeCAD.Vector(-15, -10, 0)
    doc.recompute()
    job = api.make_job(doc, box, start=(box, ["Face5"]), layer_thickness=3.0, voxel_size=1.0)
    process_events()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, job.Name)
    check(job_commands.run_selected_job(job), "run from the GUI completed")
    process_events()
    check_results_shown(job, box)
    check_layer_inspector(job)
    check_simulation(job)
    log = report_view()
    text = log.toPlainText() if log is not None else ""
    check("Traceback" not in text, "no traceback in the Report view")
    FreeCAD.closeDocument(doc.Name)


finish(run)
