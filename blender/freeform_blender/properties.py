"""Per-object settings (saved with the .blend): the edit's order, smoothness and models."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty

from .native import ff


def _order_changed(self, context):
    # Smoothness is absolute (C0..C^(k-1)): keep it in range, and "smoothest" stays smoothest.
    k1, old = int(self.order) - 1, self.get("last_order", 2) - 1
    for key in ("outer", "inner"):
        value = getattr(self, key)
        if value > k1 or value == old:
            setattr(self, key, float(k1))
    self["last_order"] = k1 + 1
    _changed(self, context)


def _changed(self, context):
    # A running edit follows its settings: precompute again in the background and show it.
    from . import operators
    operators.refresh_soon(self.id_data)


# Tooltips of the models the library lists (freeform.DEFORMATIONS); a model added there appears
# with a generic one. The item is the edit-file name in capitals (saved in .blend files).
_MODEL_TIPS = {"linear": "The paper's BCM: one dense product per frame",
               "nonlinear": "Rotation-aware BCM: large twists and bends keep their volume (iterates)"}


def _model_items():
    names = ff.DEFORMATIONS if ff is not None else ("linear",)
    return [(n.upper(), n.capitalize(), _MODEL_TIPS.get(n, f"The library's {n} model")) for n in names]


class FreeformSettings(bpy.types.PropertyGroup):
    order: EnumProperty(
        name="Stiffness", default='2', update=_order_changed,
        items=[('1', "Membrane (k=1)", "Minimal area: tent-like, C0 at the boundary"),
               ('2', "Thin plate (k=2)", "Minimal bending: smooth, C1 at the boundary"),
               ('3', "Min. curvature variation (k=3)", "Smoothest: C2 at the boundary")])
    outer: FloatProperty(
        name="Outer smoothness", min=0.0, max=2.0, default=1.0, update=_changed,
        description="Boundary smoothness at the fixed side: 0 = crease (C0), k-1 = smoothest (clamped to k-1)")
    inner: FloatProperty(
        name="Inner smoothness", min=0.0, max=2.0, default=1.0, update=_changed,
        description="Boundary smoothness at the handles: 0 = crease (C0), k-1 = smoothest (clamped to k-1)")
    anisotropic: BoolProperty(
        name="Anisotropic", default=False, update=_changed,
        description="Bend long thin supports along their whole length (operator on the support's conformal map)")
    multiresolution: BoolProperty(
        name="Keep detail", default=True, update=_changed,
        description="Multiresolution: deform a smooth base and put the detail back on it")
    deformation: EnumProperty(name="Model", default='LINEAR', update=_changed, items=_model_items())
    preserve_volume: BoolProperty(
        name="Keep volume", default=True, update=_changed,
        description="Nonlinear model: keep the enclosed volume of closed meshes against the model's necking (a drag or scale adds or removes its own)")
    active_handle: StringProperty(name="Active handle", description="The handle G/R/S move")


def _progress(_wm):
    from . import session
    obj = bpy.context.active_object
    s = session.get(obj) if obj is not None else None
    return 100.0 * s.progress[1] if s is not None else 0.0


def register():
    bpy.utils.register_class(FreeformSettings)
    bpy.types.Object.freeform = bpy.props.PointerProperty(type=FreeformSettings)
    bpy.types.WindowManager.freeform_progress = FloatProperty(  # the panel's progress bar
        name="Progress", subtype='PERCENTAGE', min=0.0, max=100.0, get=_progress)


def unregister():
    del bpy.types.WindowManager.freeform_progress
    del bpy.types.Object.freeform
    bpy.utils.unregister_class(FreeformSettings)
