"""Operators: regions, precompute, reset/apply, and edit files for scripts and batch work."""

import functools
import traceback

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import mesh_data, regions, session
from .native import UserError, failure, require


def _guarded(method, self, *args):
    try:
        return method(self, *args)
    except UserError as error:
        self.report({'ERROR'}, str(error))
    except Exception as error:  # noqa: BLE001  (a bug: still no traceback in the UI)
        traceback.print_exc()
        self.report({'ERROR'}, f"Freeform: internal error: {error} (details on the console)")
    return {'CANCELLED'}


def reported(method):
    """Errors become Blender error reports (status bar, or RuntimeError for scripts), never a
    traceback in the UI; a bug's traceback goes to the console only. Blender checks the
    argument count of execute/invoke/modal, so the wrapper keeps it."""
    if method.__code__.co_argcount == 3:
        def with_event(self, context, event):
            return _guarded(method, self, context, event)
        return functools.wraps(method)(with_event)

    def without_event(self, context):
        return _guarded(method, self, context)
    return functools.wraps(method)(without_event)


def edit_object(context):
    obj = mesh_data.active_mesh_object(context)
    mesh_data.require_edit_mode(obj)
    return obj


def _redraw():
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else ()):
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def _poll_precompute():
    """Timer: show finished background precomputes (progress redraws the panel meanwhile)."""
    busy = False
    for name, s in list(session._sessions.items()):
        if s.thread is None:
            continue
        if s.running:
            busy = True
            continue
        s.thread = None
        obj = bpy.data.objects.get(name)
        if s.error is not None or obj is None or len(obj.data.vertices) != len(s.rest):
            continue
        try:  # only over a shape this rest made (not after an undo or another tool meanwhile)
            known = s.history.get(session.shape_hash(mesh_data.positions(obj)))
            if known is not None and any(not np.array_equal(m, np.eye(4)) for m in known.values()):
                s.write(obj, {n: known.get(n, np.eye(4)) for n in s.movable})
        except Exception:  # noqa: BLE001  (a timer must survive: report on the console)
            traceback.print_exc()
    _redraw()
    return 0.1 if busy else None


def precompute_in_background(obj):
    s = session.prepare(obj, background=True)
    if s.running and not bpy.app.timers.is_registered(_poll_precompute):
        bpy.app.timers.register(_poll_precompute, first_interval=0.1)
    return s


def refresh(obj):
    """Settings changed: an object being edited precomputes again (errors show in the panel)."""
    if session.get(obj) is None:
        return
    try:
        precompute_in_background(obj)
    except UserError as error:
        session.forget(obj)
        print(error)


_pending = set()  # objects with a refresh scheduled


def refresh_soon(obj):
    """A slider drag changes a setting many times: one refresh 0.3 s after the first change.
    Scripts (no event loop, so no timers in background mode) refresh at once."""
    if bpy.app.background:
        refresh(obj)
        return
    name = obj.name
    if name in _pending:
        return

    def fire():
        _pending.discard(name)
        target = bpy.data.objects.get(name)
        if target is not None:
            refresh(target)

    _pending.add(name)
    bpy.app.timers.register(fire, first_interval=0.3)


def prepared(obj, wait=True):
    """The object's session with its solver, computed now if needed; a background precompute
    is waited for (scripts) or reported (wait=False: the modal G/R/S keeps the UI responsive)."""
    s = session.prepare(obj)
    if s.running and not wait:
        raise UserError("Freeform: still precomputing ({} {:.0%}); try again when it is done".format(*s.progress))
    s.wait()
    return s


class FREEFORM_OT_assign(bpy.types.Operator):
    """Assign the selected vertices to the support, a handle or an immovable handle"""
    bl_idname = "freeform.assign"
    bl_label = "Assign to Freeform Region"
    bl_options = {'REGISTER', 'UNDO'}

    role: EnumProperty(items=[('SUPPORT', "Support", "The vertices that may move"),
                              ('HANDLE', "Handle", "Vertices moved by the transform"),
                              ('IMMOVABLE', "Immovable handle", "Vertices held in place inside the support")])
    handle: StringProperty(description="An existing handle group (empty: a new one)")

    @reported
    def execute(self, context):
        obj = edit_object(context)
        name = regions.assign(obj, self.role, self.handle)
        refresh(obj)
        if self.role == 'HANDLE':
            obj.freeform.active_handle = name
        self.report({'INFO'}, f"Freeform: selection assigned to {name}")
        return {'FINISHED'}


class FREEFORM_OT_remove(bpy.types.Operator):
    """Take the selected vertices out of the support and all handles"""
    bl_idname = "freeform.remove"
    bl_label = "Remove from Freeform Regions"
    bl_options = {'REGISTER', 'UNDO'}

    @reported
    def execute(self, context):
        obj = edit_object(context)
        regions.remove_selected(obj)
        refresh(obj)
        return {'FINISHED'}


class FREEFORM_OT_set_active(bpy.types.Operator):
    """Make this handle the one G/R/S move"""
    bl_idname = "freeform.set_active"
    bl_label = "Set Active Handle"
    bl_options = {'INTERNAL'}

    handle: StringProperty()

    @reported
    def execute(self, context):
        obj = mesh_data.active_mesh_object(context)
        obj.freeform.active_handle = self.handle
        return {'FINISHED'}


class FREEFORM_OT_precompute(bpy.types.Operator):
    """Precompute the solver for the current regions and settings (in the background)"""
    bl_idname = "freeform.precompute"
    bl_label = "Precompute"

    background: BoolProperty(default=True, description="Return at once and show progress in the panel")

    @reported
    def execute(self, context):
        obj = mesh_data.active_mesh_object(context)
        if self.background:
            precompute_in_background(obj)
        else:
            prepared(obj)
        return {'FINISHED'}


class FREEFORM_OT_reset(bpy.types.Operator):
    """Move every handle back to where it was when the edit started"""
    bl_idname = "freeform.reset"
    bl_label = "Reset Handles"
    bl_options = {'REGISTER', 'UNDO'}

    @reported
    def execute(self, context):
        obj = mesh_data.active_mesh_object(context)
        s = prepared(obj)
        s.write(obj, {n: np.eye(4) for n in s.movable})
        return {'FINISHED'}


class FREEFORM_OT_apply(bpy.types.Operator):
    """Keep the deformed shape as the new rest shape: handles start again from identity"""
    bl_idname = "freeform.apply"
    bl_label = "Apply"
    bl_options = {'REGISTER', 'UNDO'}

    @reported
    def execute(self, context):
        obj = mesh_data.active_mesh_object(context)
        session.forget(obj)
        self.report({'INFO'}, "Freeform: the current shape is the new rest shape")
        return {'FINISHED'}


class FREEFORM_OT_apply_edit(bpy.types.Operator, ImportHelper):
    """Apply an edit file (freeform deform's JSON) to the active mesh; selectors are resolved on it"""
    bl_idname = "freeform.apply_edit"
    bl_label = "Apply Edit File"
    bl_options = {'REGISTER', 'UNDO'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    @reported
    def execute(self, context):
        ff = require()
        obj = mesh_data.active_mesh_object(context)
        rest = mesh_data.positions(obj)
        tris = mesh_data.triangles(obj)
        try:
            mesh = ff.Mesh(rest, tris)
            edit = ff.read_edit(self.filepath, mesh)
            out = ff.deform(mesh, edit)
        except (ff.Error, OSError) as error:
            raise failure(obj, error) from None
        mesh_data.write_positions(obj, out)
        session.forget(obj)  # a shape no session made: the next edit starts from it
        self.report({'INFO'}, f"Freeform: applied {bpy.path.basename(self.filepath)}")
        return {'FINISHED'}


class FREEFORM_OT_export_edit(bpy.types.Operator, ExportHelper):
    """Write the regions, settings and handle transforms as an edit file for freeform deform"""
    bl_idname = "freeform.export_edit"
    bl_label = "Export Edit File"

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})
    mesh_filepath: StringProperty(
        name="Rest mesh", subtype='FILE_PATH',
        description="Also write the triangulated rest shape the edit applies to (.obj, .off, .ply, .stl)")

    @reported
    def execute(self, context):
        ff = require()
        obj = mesh_data.active_mesh_object(context)
        s = prepared(obj)  # current regions and settings; a moved shape keeps its transforms
        s.write(obj, s.transforms)  # so what Blender shows is what the file replays
        rest, tris, transforms = s.rest, s.tris, s.transforms
        data, _ = session.edit_dict(obj, regions.read(obj), transforms, tris)
        try:
            mesh = ff.Mesh(rest, tris)
            ff.write_edit(self.filepath, ff.Edit.from_dict(data, mesh, name=obj.name))
            if self.mesh_filepath:
                ff.write_mesh(bpy.path.abspath(self.mesh_filepath), rest, tris)
        except (ff.Error, OSError) as error:
            raise failure(obj, error) from None
        self.report({'INFO'}, f"Freeform: wrote {self.filepath}")
        return {'FINISHED'}


classes = (FREEFORM_OT_assign, FREEFORM_OT_remove, FREEFORM_OT_set_active, FREEFORM_OT_precompute,
           FREEFORM_OT_reset, FREEFORM_OT_apply, FREEFORM_OT_apply_edit, FREEFORM_OT_export_edit)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    if bpy.app.timers.is_registered(_poll_precompute):
        bpy.app.timers.unregister(_poll_precompute)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
