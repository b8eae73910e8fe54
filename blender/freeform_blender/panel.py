"""The "Freeform" tab of the 3D Viewport's sidebar (N)."""

import bpy

from . import regions, session
from .native import IMPORT_ERROR


class VIEW3D_PT_freeform(bpy.types.Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Freeform"
    bl_label = "Freeform"

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == 'MESH'

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        if IMPORT_ERROR:
            layout.alert = True
            layout.label(text=IMPORT_ERROR, icon='ERROR')
            return
        if obj.mode == 'EDIT':
            self.draw_regions(layout, obj)
            self.draw_settings(layout, obj)
            self.draw_solver(context, layout, obj)
        else:
            layout.label(text="Tab into Edit Mode to set regions and drag handles", icon='INFO')
        col = layout.column(align=True)
        col.operator("freeform.apply_edit", icon='FILE_TICK', text="Apply Edit File...")
        col.operator("freeform.export_edit", icon='EXPORT', text="Export Edit File...")

    def draw_regions(self, layout, obj):
        box = layout.box()
        box.label(text="Regions (selected vertices)")
        col = box.column(align=True)
        col.operator("freeform.assign", text="Assign to Support", icon='MOD_SMOOTH').role = 'SUPPORT'
        col.operator("freeform.assign", text="New Handle", icon='EMPTY_ARROWS').role = 'HANDLE'
        grow = col.row()
        grow.enabled = bool(obj.freeform.active_handle)
        op = grow.operator("freeform.assign", text="Assign to Active Handle", icon='ADD')
        op.role, op.handle = 'HANDLE', obj.freeform.active_handle
        col.operator("freeform.assign", text="New Immovable Handle", icon='PINNED').role = 'IMMOVABLE'
        col.operator("freeform.remove", text="Remove from Regions", icon='REMOVE')
        handles = regions.handle_groups(obj)
        if regions.SUPPORT not in obj.vertex_groups:
            box.label(text="No support yet", icon='DOT')
        for name, movable in handles:
            row = box.row()
            if movable:
                row.operator("freeform.set_active", text=name, icon='EMPTY_ARROWS',
                             depress=name == obj.freeform.active_handle).handle = name
            else:
                row.label(text=name, icon='PINNED')

    def draw_settings(self, layout, obj):
        s = obj.freeform
        col = layout.column()
        col.label(text="Stiffness")
        col.prop(s, "order", text="")
        k1 = int(s.order) - 1
        sub = col.column(align=True)
        sub.enabled = k1 > 0
        sub.prop(s, "outer", slider=True, text=f"Outer C0..C{k1}")
        sub.prop(s, "inner", slider=True, text=f"Inner C0..C{k1}")
        col.prop(s, "anisotropic")
        col.prop(s, "multiresolution")
        col.prop(s, "deformation", text="")
        sub = col.column()
        sub.enabled = s.deformation == 'NONLINEAR'
        sub.prop(s, "preserve_volume")

    def draw_solver(self, context, layout, obj):
        s = session.get(obj)
        box = layout.box()
        if s is not None and s.running:
            stage, done = s.progress
            row = box.row()
            row.enabled = False  # a bar, not a slider the user could drag
            row.prop(context.window_manager, "freeform_progress", text=stage, slider=True)
        elif s is not None and s.error is not None:
            box.alert = True
            box.label(text=str(s.error)[:120], icon='ERROR')
        elif s is not None and s.solver is not None:
            counts = s.solver.stats["counts"]
            box.label(text=f"Ready: {counts['free']} free vertices", icon='CHECKMARK')
        box.operator("freeform.precompute", icon='FILE_REFRESH')
        row = box.row(align=True)
        row.operator_context = 'INVOKE_DEFAULT'
        row.operator("freeform.transform", text="Move").mode = 'TRANSLATE'
        row.operator("freeform.transform", text="Rotate").mode = 'ROTATE'
        row.operator("freeform.transform", text="Scale").mode = 'RESIZE'
        row = box.row(align=True)
        row.operator("freeform.reset", text="Reset", icon='LOOP_BACK')
        row.operator("freeform.apply", text="Apply", icon='CHECKMARK')


def register():
    bpy.utils.register_class(VIEW3D_PT_freeform)


def unregister():
    bpy.utils.unregister_class(VIEW3D_PT_freeform)
