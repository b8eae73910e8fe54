"""G/R/S of the active handle: modal with Blender's habits (mouse, X/Y/Z axis locks, typed
values, G/R/S switch, Esc/right click cancel, Enter/click confirm as one undo step) and the
same operator non-modal for scripts: bpy.ops.freeform.transform(mode='ROTATE', angle=..., axis=...).
Transforms are in world space around the handle's current centroid, like Blender's defaults."""

import math
import traceback

import bpy
import numpy as np
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty, StringProperty
from bpy_extras import view3d_utils
from mathutils import Vector

from . import mesh_data
from .native import UserError
from .operators import prepared, reported

_AXES = {'X': (1.0, 0.0, 0.0), 'Y': (0.0, 1.0, 0.0), 'Z': (0.0, 0.0, 1.0)}
_DIGITS = {**{n: str(i) for i, n in enumerate(("ZERO", "ONE", "TWO", "THREE", "FOUR", "FIVE", "SIX", "SEVEN",
                                                "EIGHT", "NINE"))},
           **{f"NUMPAD_{i}": str(i) for i in range(10)}, "PERIOD": ".", "NUMPAD_PERIOD": "."}
_MODES = {'G': 'TRANSLATE', 'R': 'ROTATE', 'S': 'RESIZE'}


def about(pivot, linear):
    """4x4: x -> pivot + linear (x - pivot)."""
    m = np.eye(4)
    m[:3, :3] = linear
    m[:3, 3] = pivot - linear @ pivot
    return m


def rotation(axis, angle):
    a = np.asarray(axis, dtype=float)
    n = np.linalg.norm(a)
    if n == 0:
        raise UserError("Freeform: the rotation axis is the zero vector")
    x, y, z = a / n
    c, s = math.cos(angle), math.sin(angle)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return c * np.eye(3) + s * k + (1 - c) * np.outer((x, y, z), (x, y, z))


class FREEFORM_OT_transform(bpy.types.Operator):
    """Move, rotate or scale the active Freeform handle (G/R/S, X/Y/Z, type a value)"""
    bl_idname = "freeform.transform"
    bl_label = "Freeform Transform"
    bl_options = {'REGISTER', 'UNDO', 'BLOCKING', 'GRAB_CURSOR'}

    mode: EnumProperty(items=[('TRANSLATE', "Move", ""), ('ROTATE', "Rotate", ""), ('RESIZE', "Scale", "")])
    translate: FloatVectorProperty(name="Move", subtype='TRANSLATION', size=3)
    angle: FloatProperty(name="Angle", subtype='ANGLE')
    axis: FloatVectorProperty(name="Axis", subtype='DIRECTION', size=3, default=(0.0, 0.0, 1.0))
    scale: FloatVectorProperty(name="Scale", subtype='XYZ', size=3, default=(1.0, 1.0, 1.0))
    handle: StringProperty(name="Handle", description="A movable handle group (empty: the active handle)")

    # the world-space map of the current properties, about the handle's current centroid
    def delta(self, obj, s, name):
        world = np.array(obj.matrix_world)
        pivot = (world @ np.append(s.pivot(name, self.start), 1.0))[:3]  # where the handle was at the start
        if self.mode == 'TRANSLATE':
            d = about(pivot, np.eye(3))
            d[:3, 3] = self.translate
        elif self.mode == 'ROTATE':
            d = about(pivot, rotation(self.axis, self.angle))
        else:
            if any(abs(f) < 1e-12 for f in self.scale):
                raise UserError("Freeform: a zero scale flattens the handle")
            d = about(pivot, np.diag(self.scale))
        return np.linalg.inv(world) @ d @ world  # in the object's own coordinates

    def target(self, obj, s):
        name = self.handle or obj.freeform.active_handle
        if name not in s.movable:
            if len(s.movable) == 1 and not self.handle:
                name = s.movable[0]
            else:
                raise UserError(f"Freeform: '{name}' is not a movable handle of '{obj.name}' "
                                f"(handles: {', '.join(s.movable)}); pick one in the panel")
        return name

    def moved(self, obj):
        """The handle transforms of the current properties."""
        t = dict(self.start)
        t[self.handle_name] = self.delta(obj, self.session, self.handle_name) @ self.start[self.handle_name]
        return t

    @reported
    def execute(self, context):
        obj = mesh_data.active_mesh_object(context)
        self.session = prepared(obj)
        self.handle_name = self.target(obj, self.session)
        self.start = dict(self.session.transforms)
        self.session.write(obj, self.moved(obj))
        return {'FINISHED'}

    # modal --------------------------------------------------------------------------------
    @reported
    def invoke(self, context, event):
        obj = mesh_data.active_mesh_object(context)
        mesh_data.require_edit_mode(obj)
        if context.area is None or context.area.type != 'VIEW_3D':
            return self.execute(context)
        self.session = prepared(obj, wait=False)
        self.handle_name = self.target(obj, self.session)
        self.start = dict(self.session.transforms)
        self.region = next(r for r in context.area.regions if r.type == 'WINDOW')
        self.rv3d = context.area.spaces.active.region_3d
        world = np.array(obj.matrix_world)
        self.pivot = Vector((world @ np.append(self.session.pivot(self.handle_name), 1.0))[:3])
        self.mouse0 = self.mouse = self.region_mouse(event)
        self.lock, self.typed = None, ""
        self.translate, self.angle, self.scale = (0, 0, 0), 0.0, (1, 1, 1)
        self.saved = mesh_data.positions(obj)  # Esc/right click restore exactly this
        self.converged = True
        # Timer ticks show the nonlinear worker's newer iterates between mouse moves (freeform-editor too).
        self.timer = context.window_manager.event_timer_add(0.02, window=context.window)
        context.window_manager.modal_handler_add(self)
        self.status(context)
        return {'RUNNING_MODAL'}

    def region_mouse(self, event):
        return Vector((event.mouse_x - self.region.x, event.mouse_y - self.region.y))

    def status(self, context):
        what = {'TRANSLATE': "Move", 'ROTATE': "Rotate", 'RESIZE': "Scale"}[self.mode]
        if self.mode == 'TRANSLATE':
            value = "  ".join(f"{c:.4g}" for c in self.translate)
        elif self.mode == 'ROTATE':
            value = f"{math.degrees(self.angle):.2f}°"
        else:
            value = "  ".join(f"{c:.4g}" for c in self.scale)
        lock = f" along {self.lock}" if self.lock else ""
        typed = f" [{self.typed}|]" if self.typed else ""
        refining = "" if self.converged else "  (refining)"
        context.area.header_text_set(f"Freeform {what} {self.handle_name}{lock}: {value}{typed}{refining}")
        context.workspace.status_text_set("Click/Enter: confirm   Right click/Esc: cancel   G/R/S: mode   "
                                          "X/Y/Z: axis   type a value")

    def update(self, context):
        axis = Vector(_AXES[self.lock]) if self.lock else None
        number = None
        if self.typed not in ("", "-", ".", "-."):
            number = float(self.typed)
        r, rv3d, p = self.region, self.rv3d, self.pivot
        if self.mode == 'TRANSLATE':
            if number is not None:
                d = (axis or Vector(_AXES['X'])) * number
            else:
                a = view3d_utils.region_2d_to_location_3d(r, rv3d, self.mouse0, p)
                b = view3d_utils.region_2d_to_location_3d(r, rv3d, self.mouse, p)
                d = b - a if axis is None else axis * (b - a).dot(axis)
            self.translate = tuple(d)
        else:
            centre = view3d_utils.location_3d_to_region_2d(r, rv3d, p) or Vector((0, 0))
            u, v = self.mouse0 - centre, self.mouse - centre
            if self.mode == 'ROTATE':
                towards_viewer = rv3d.view_rotation @ Vector((0, 0, 1))
                spin = math.atan2(u.x * v.y - u.y * v.x, u.dot(v))
                if axis is None:
                    self.axis, self.angle = tuple(towards_viewer), spin
                else:
                    self.axis = tuple(axis)
                    self.angle = spin if axis.dot(towards_viewer) >= 0 else -spin
                if number is not None:
                    self.angle = math.radians(number)
            else:
                f = number if number is not None else v.length / max(u.length, 1.0)
                self.scale = tuple(f if (self.lock is None or self.lock == c) else 1.0 for c in "XYZ")
        obj = context.active_object
        self.converged = self.session.drag(obj, self.moved(obj))
        self.status(context)

    def finish(self, context):
        context.window_manager.event_timer_remove(self.timer)
        context.area.header_text_set(None)
        context.workspace.status_text_set(None)

    def restore(self, context):
        obj = context.active_object
        mesh_data.write_positions(obj, self.saved)
        self.session.transforms = dict(self.start)

    def modal(self, context, event):
        try:
            return self.handle_event(context, event)
        except Exception as error:  # noqa: BLE001  (restore and report, never a half-done drag)
            self.restore(context)
            self.finish(context)
            if not isinstance(error, UserError):
                traceback.print_exc()
            self.report({'ERROR'}, str(error) if isinstance(error, UserError) else f"Freeform: internal error: {error}")
            return {'CANCELLED'}

    def handle_event(self, context, event):
        t, pressed = event.type, event.value == 'PRESS'
        if t == 'TIMER':
            if not self.converged:  # ours or another timer: show the worker's newest iterate
                self.converged = self.session.refine(context.active_object)
                self.status(context)
            return {'RUNNING_MODAL'}
        if t == 'MOUSEMOVE':
            self.mouse = self.region_mouse(event)
        elif t in ('MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE'):
            return {'PASS_THROUGH'}
        elif not pressed:
            return {'RUNNING_MODAL'}
        elif t in ('LEFTMOUSE', 'RET', 'NUMPAD_ENTER'):
            # The undo step holds the model's solution solved from scratch: the same shape as
            # `freeform deform` of the edit, whatever path the drag's iterations took.
            self.session.write(context.active_object, self.session.transforms)
            self.converged = True
            self.finish(context)
            return {'FINISHED'}
        elif t in ('RIGHTMOUSE', 'ESC'):
            self.restore(context)
            self.finish(context)
            return {'CANCELLED'}
        elif t in _MODES:
            self.mode, self.typed = _MODES[t], ""
        elif t in _AXES:
            self.lock = None if self.lock == t else t
        elif t in _DIGITS:
            self.typed += _DIGITS[t]
        elif t in ('MINUS', 'NUMPAD_MINUS'):
            self.typed = self.typed[1:] if self.typed.startswith("-") else "-" + self.typed
        elif t == 'BACK_SPACE':
            self.typed = self.typed[:-1]
        else:
            return {'RUNNING_MODAL'}
        try:
            self.update(context)
        except (ValueError, UserError):  # "1.2." or "0" while typing: wait for the next key
            pass
        return {'RUNNING_MODAL'}


def register():
    bpy.utils.register_class(FREEFORM_OT_transform)


def unregister():
    bpy.utils.unregister_class(FREEFORM_OT_transform)
