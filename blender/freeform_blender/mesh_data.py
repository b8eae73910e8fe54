"""Blender mesh <-> numpy: vertex positions (float32 in Blender, float64 here) and the
triangulation the solver works on. Vertex i is Blender's vertex i; faces are never changed."""

import bmesh
import numpy as np

from .native import UserError


def active_mesh_object(context):
    obj = context.active_object
    if obj is None or obj.type != 'MESH':
        raise UserError("Freeform: no mesh object is active: select a mesh and make it active")
    return obj


def require_edit_mode(obj):
    if obj.mode != 'EDIT':
        raise UserError(f"Freeform: '{obj.name}' is not in Edit Mode: press Tab, then select vertices")


def sync(obj):
    """Make obj.data current (Edit Mode keeps its own copy until told)."""
    if obj.mode == 'EDIT':
        obj.update_from_editmode()


def positions(obj):
    sync(obj)
    me = obj.data
    co = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def triangles(obj):
    """Blender's own triangulation of quads and n-gons (what its viewport draws)."""
    sync(obj)
    me = obj.data
    me.calc_loop_triangles()
    tris = np.empty(len(me.loop_triangles) * 3, dtype=np.int64)
    me.loop_triangles.foreach_get("vertices", tris)
    return tris.reshape(-1, 3)


def write_positions(obj, values, rows=None):
    """Write float64 positions (all rows, or the given ones) back into the mesh."""
    me = obj.data
    if obj.mode == 'EDIT':
        bm = bmesh.from_edit_mesh(me)
        bm.verts.ensure_lookup_table()
        verts = bm.verts
        if rows is None:
            rows = range(len(verts))
        for i, p in zip(rows, values[rows].tolist()):
            verts[i].co = p
        bmesh.update_edit_mesh(me, loop_triangles=True, destructive=False)
        return
    co = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    if rows is None:
        co[:] = values
    else:
        co[rows] = values[rows]
    me.vertices.foreach_set("co", co.ravel())
    me.update()
