"""Screenshots of the Blender add-on for docs/blender.md (run by scripts/blender-screenshots.sh):
a real Blender window on Xvfb, driven by xdotool (Blender's own event simulation cannot click
the sidebar's tabs)."""

import os
import subprocess
import sys
import traceback

import bmesh
import bpy
import numpy as np

OUT = os.environ["FREEFORM_SHOTS"]


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == 'VIEW_3D')
    return win, area, next(r for r in area.regions if r.type == 'WINDOW')


def override():
    win, area, region = view3d()
    return bpy.context.temp_override(window=win, area=area, region=region)


def plane(n, name):
    import freeform_blender
    m = freeform_blender.native.ff.make_bumpy_plane(n, n, 0.06, 2.0, 2.0, 2.0)
    me = bpy.data.meshes.new(name)
    me.from_pydata(m.vertices.tolist(), [], m.faces.tolist())
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    return obj


def regions(obj, support, handle, immovable=None):
    bm = bmesh.from_edit_mesh(obj.data)
    co = np.array([v.co[:] for v in bm.verts])
    d = np.linalg.norm(co[:, :2] - [1.0, 1.0], axis=1)
    todo = [(d < support, 'SUPPORT'), (d < handle, 'HANDLE')]
    if immovable:
        todo.append((np.linalg.norm(co[:, :2] - [1.45, 1.0], axis=1) < immovable, 'IMMOVABLE'))
    for mask, role in todo + [(np.zeros(len(d)), None)]:
        for v, on in zip(bm.verts, mask):
            v.select = bool(on)
        bm.select_flush(False)
        bmesh.update_edit_mesh(obj.data)
        if role:
            bpy.ops.freeform.assign(role=role)


def setup():
    bpy.ops.preferences.addon_install(filepath=os.environ["FREEFORM_BLENDER_ZIP"], overwrite=True)
    bpy.ops.preferences.addon_enable(module="freeform_blender")
    bpy.context.preferences.view.smooth_view = 0
    with override():
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj)
        obj = plane(48, "BumpyPlane")
        bpy.ops.object.mode_set(mode='EDIT')
        regions(obj, 0.85, 0.15, 0.12)
        obj.freeform.order = '3'
        bpy.ops.freeform.transform(mode='TRANSLATE', translate=(0.0, 0.0, 0.6))
        win, area, region = view3d()
        space = area.spaces.active
        space.show_region_ui = True
        space.overlay.show_stats = True
        from mathutils import Euler
        r3 = space.region_3d
        r3.view_rotation = Euler((1.1, 0, 0.55)).to_quaternion()
        r3.view_distance = 4.0
        r3.view_location = (1.0, 1.0, 0.2)


def xdo(*args):
    subprocess.run(["xdotool", *map(str, args)], check=True)


def point(x, y):
    """Window coordinates (origin bottom left) -> screen (the window fills the screen)."""
    return x, view3d()[0].height - y


def click_freeform_tab():
    _, area, _ = view3d()
    ui = next(r for r in area.regions if r.type == 'UI')
    xdo("mousemove", 700, 700, "click", 1)  # closes the splash screen
    xdo("mousemove", *point(ui.x + ui.width - 10, ui.y + ui.height - 181), "click", 1)


def shot(name, height=720, scale=0.8):
    """The 3D view without its empty floor, scaled down (small files in the repository)."""
    win, area, _ = view3d()
    path = os.path.join(OUT, name)
    with bpy.context.temp_override(window=win, area=area):
        bpy.ops.screen.screenshot_area(filepath=path)
    full = bpy.data.images.load(path)
    w, h = full.size
    pixels = np.empty(w * h * 4, dtype=np.float32)
    full.pixels.foreach_get(pixels)
    crop = pixels.reshape(h, w, 4)[h - height:]  # rows start at the bottom
    out = bpy.data.images.new(name, crop.shape[1], crop.shape[0])
    out.pixels.foreach_set(np.ascontiguousarray(crop).ravel())
    out.scale(int(crop.shape[1] * scale), int(crop.shape[0] * scale))
    out.filepath_raw, out.file_format = path, 'PNG'
    bpy.context.scene.render.image_settings.compression = 100
    out.save()
    print("wrote", name, out.size[:], flush=True)


def move(dx, dy):
    _, _, region = view3d()
    xdo("mousemove", *point(region.x + region.width // 2 + dx, region.y + region.height // 2 + dy))


def keys(*names):
    xdo("key", *names)


def invoke(mode):
    with override():
        bpy.ops.freeform.transform('INVOKE_DEFAULT', mode=mode)


def big_plane():
    with override():
        bpy.ops.object.mode_set(mode='OBJECT')
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj)
        obj = plane(260, "BigPlane")
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.mesh.select_mode(type='FACE')  # no vertex dots on 68k vertices
        regions(obj, 0.95, 0.1)
        bpy.ops.freeform.precompute()  # in the background: the panel shows its progress


STEPS = [
    (1.0, setup), (1.0, click_freeform_tab), (1.5, lambda: shot("blender-panel.png")),
    (0.3, lambda: move(-60, -80)), (0.3, lambda: invoke('ROTATE')), (0.3, lambda: move(-140, 40)),
    (0.3, lambda: keys('y', 'minus', '2', '5')), (1.0, lambda: shot("blender-modal.png")),
    (0.3, lambda: keys('Return')), (0.3, big_plane), (1.2, lambda: shot("blender-progress.png")),
]


def step():
    delay, fn = STEPS.pop(0)
    try:
        fn()
    except Exception:
        traceback.print_exc()
        os._exit(1)
    if STEPS:
        return STEPS[0][0]
    sys.stdout.flush()
    os._exit(0)


bpy.app.timers.register(step, first_interval=STEPS[0][0])
