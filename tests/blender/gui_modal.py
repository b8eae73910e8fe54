"""The modal G/R/S as a user drives it: a real Blender window (Xvfb + llvmpipe) fed with
simulated events (blender --enable-event-simulate): mouse moves, axis locks, typed values,
Enter to confirm (one undo step), Esc and right click to cancel. Steps run from a timer;
exits 0 when every check passed (ctest test blender_modal)."""

import math
import os
import sys
import traceback

import bmesh
import bpy
import numpy as np

checks = []


def check(what, ok):
    checks.append((what, bool(ok)))
    print(("ok   " if ok else "FAIL ") + what, flush=True)


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == 'VIEW_3D')
    return win, area, next(r for r in area.regions if r.type == 'WINDOW')


def coords(obj):
    obj.update_from_editmode()
    co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


state = {}


def setup():
    bpy.ops.preferences.addon_install(filepath=os.environ["FREEFORM_BLENDER_ZIP"], overwrite=True)
    bpy.ops.preferences.addon_enable(module="freeform_blender")
    win, area, region = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj)
        bpy.ops.mesh.primitive_cube_add(size=2.0)
        obj = bpy.context.active_object
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.mesh.select_all(action='SELECT')
        bpy.ops.mesh.subdivide(number_cuts=7)
        bm = bmesh.from_edit_mesh(obj.data)
        rest = np.array([v.co[:] for v in bm.verts], dtype=np.float32)
        for mask, role in ((rest[:, 2] > -0.6, 'SUPPORT'), (rest[:, 2] > 0.9, 'HANDLE')):
            for v, on in zip(bm.verts, mask):
                v.select = bool(on)
            bm.select_flush(False)
            bmesh.update_edit_mesh(obj.data)
            bpy.ops.freeform.assign(role=role)
        bpy.ops.freeform.precompute(background=False)
        bpy.ops.ed.undo_push(message="regions")
    state.update(obj=obj, rest=rest, handle=rest[:, 2] > 0.9, fixed=rest[:, 2] <= -0.6)


def move(dx, dy):
    win, area, region = view3d()
    win.event_simulate('MOUSEMOVE', 'NOTHING', x=region.x + region.width // 2 + dx, y=region.y + region.height // 2 + dy)


def keys(*names):
    win = view3d()[0]
    for name in names:
        win.event_simulate(name, 'PRESS')
        win.event_simulate(name, 'RELEASE')


def invoke(mode):
    win, area, region = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        state["invoked"] = bpy.ops.freeform.transform('INVOKE_DEFAULT', mode=mode)


def typed_move_confirmed():
    p = coords(state["obj"])
    rest, h = state["rest"], state["handle"]
    check("invoke runs modal", state["invoked"] == {'RUNNING_MODAL'})
    check("G Z 0.5 Enter moves the handle by (0, 0, 0.5)", np.abs(p[h] - (rest[h] + [0, 0, 0.5])).max() < 1e-6)
    check("the fixed part stays", np.array_equal(p[state["fixed"]], rest[state["fixed"]]))
    state["moved"] = p


def rotate_cancelled():
    check("R, mouse, Esc restores the confirmed shape exactly", np.array_equal(coords(state["obj"]), state["moved"]))


def rotate_typed_then_right_click():
    check("right click cancels", np.array_equal(coords(state["obj"]), state["moved"]))


def scale_x_confirmed():
    p, m, h = coords(state["obj"]), state["moved"], state["handle"]
    c = m[h].mean(axis=0)
    expected = (m[h] - c) * [2.0, 1.0, 1.0] + c
    check("S X 2 Enter scales the handle along x about its centroid", np.abs(p[h] - expected).max() < 1e-5)


def undo():
    win, area, region = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.ed.undo()
    check("undo takes back the scale (one step)", np.array_equal(coords(bpy.context.active_object), state["moved"]))
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.ed.undo()
    check("undo again restores the input exactly", np.array_equal(coords(bpy.context.active_object), state["rest"]))


def rotate_mouse():
    p, m, h = coords(state["obj"]), state["moved"], state["handle"]
    c = m[h].mean(axis=0)
    angle = math.degrees(math.atan2(np.linalg.norm(np.cross(p[h][0] - c, m[h][0] - c)), np.dot(p[h][0] - c, m[h][0] - c)))
    check(f"R with the mouse rotates the handle ({angle:.1f} degrees)", angle > 5)


def nonlinear_setup():
    obj = state["obj"]
    obj.freeform.deformation = 'NONLINEAR'
    win, area, region = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.freeform.precompute(background=False)
        bpy.ops.ed.undo_push(message="nonlinear")
    state["before_nonlinear"] = coords(obj)


def nonlinear_confirmed():
    import freeform_blender.session as session
    obj = state["obj"]
    dragged = coords(obj)
    s = session.get(obj)
    cold = s.evaluate()  # the same transforms solved from scratch
    rest, h = state["rest"], state["handle"]
    check("nonlinear G Y 0.6 Enter: handle moved by (0, 0.6, 0) more", np.abs(dragged[h] - (state["before_nonlinear"][h] + [0, 0.6, 0])).max() < 1e-5)
    check("the confirmed nonlinear drag is the model's solution (the cold solve to 1e-4)", np.abs(dragged - cold).max() < 1e-4)
    check("the nonlinear drag moved the support", np.abs(dragged - state["before_nonlinear"]).max() > 0.5)


STEPS = [
    setup, lambda: move(0, 0), lambda: invoke('TRANSLATE'), lambda: move(40, 25),
    lambda: keys('Z', 'ZERO', 'PERIOD', 'FIVE'), lambda: keys('RET'), typed_move_confirmed,
    lambda: move(0, 0), lambda: invoke('ROTATE'), lambda: move(120, 80), rotate_mouse, lambda: keys('ESC'),
    rotate_cancelled,
    lambda: invoke('TRANSLATE'), lambda: keys('R', 'NINE', 'ZERO'), lambda: keys('RIGHTMOUSE'),
    rotate_typed_then_right_click,
    lambda: invoke('RESIZE'), lambda: move(-50, 10), lambda: keys('X', 'TWO'), lambda: keys('RET'), scale_x_confirmed,
    undo, nonlinear_setup, lambda: move(0, 0), lambda: invoke('TRANSLATE'), lambda: move(30, 30), lambda: move(60, 40),
    lambda: keys('Y', 'ZERO', 'PERIOD', 'SIX'), lambda: keys('RET'), nonlinear_confirmed,
]


def step():
    try:
        STEPS.pop(0)()
    except Exception:  # a failing step fails the test, with its traceback
        traceback.print_exc()
        checks.append(("step raised", False))
        STEPS.clear()
    if STEPS:
        return 0.2
    failed = [w for w, ok in checks if not ok]
    print(f"{len(checks) - len(failed)} of {len(checks)} checks passed", flush=True)
    sys.stdout.flush()
    os._exit(1 if failed or not checks else 0)


bpy.app.timers.register(step, first_interval=1.0)
