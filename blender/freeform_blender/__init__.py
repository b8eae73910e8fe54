"""Freeform for Blender: real-time freeform modeling (Botsch & Kobbelt 2004) of mesh objects,
on the freeform Python module bundled in this package. docs/blender.md."""

bl_info = {
    "name": "Freeform",
    "author": "Freeform developers",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "3D Viewport > Sidebar (N) > Freeform, in Edit Mode",
    "description": "Smooth, detail-preserving shape edits: support, handles, boundary smoothness, G/R/S",
    "category": "Mesh",
}

import bpy  # noqa: E402

from . import operators, panel, properties, session, transform  # noqa: E402

_modules = (properties, operators, transform, panel)


@bpy.app.handlers.persistent
def _forget_all(*_):
    session.forget_all()


def register():
    for m in _modules:
        m.register()
    bpy.app.handlers.load_pre.append(_forget_all)


def unregister():
    if _forget_all in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(_forget_all)
    session.forget_all()
    for m in reversed(_modules):
        m.unregister()
