"""Support and handles as vertex groups, so they save with the .blend and show in Blender's
own Vertex Groups panel: freeform_support, freeform_handle_N, freeform_immovable_N."""

import re

import bmesh
import numpy as np

from .native import UserError

SUPPORT = "freeform_support"
_HANDLE = re.compile(r"^freeform_(handle|immovable)_(\d+)$")


def handle_groups(obj):
    """(name, movable) of the handle groups: movable ones first, each kind by number."""
    found = []
    for g in obj.vertex_groups:
        m = _HANDLE.match(g.name)
        if m:
            found.append((m.group(1) != "handle", int(m.group(2)), g.name))
    return [(name, not immovable) for immovable, _, name in sorted(found)]


def new_handle_name(obj, movable):
    used = [int(_HANDLE.match(n).group(2)) for n, m in handle_groups(obj) if m == movable]
    return f"freeform_{'handle' if movable else 'immovable'}_{max(used, default=0) + 1}"


def _edit_bmesh(obj):
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    return bm, bm.verts.layers.deform.verify()


def assign(obj, role, handle=""):
    """Put the selected vertices into the support ('SUPPORT'), a handle ('HANDLE', 'IMMOVABLE';
    handle = an existing group name or "" for a new one). A handle's vertices join the support and
    leave every other handle (handles must not overlap). Returns the group's name."""
    bm, layer = _edit_bmesh(obj)
    selected = [v for v in bm.verts if v.select]
    if not selected:
        raise UserError("Freeform: no vertex is selected: select the vertices to assign first")
    if role == 'SUPPORT':
        name = SUPPORT
    elif handle:
        if handle not in dict(handle_groups(obj)):
            raise UserError(f"Freeform: there is no handle '{handle}' on '{obj.name}'")
        name = handle
    else:
        name = new_handle_name(obj, role == 'HANDLE')
    targets = [name] if role == 'SUPPORT' else [name, SUPPORT]
    index = {}
    for n in targets:
        group = obj.vertex_groups.get(n) or obj.vertex_groups.new(name=n)
        index[n] = group.index
    others = [obj.vertex_groups[n].index for n, _ in handle_groups(obj) if n != name] if role != 'SUPPORT' else []
    for v in selected:
        weights = v[layer]
        for gi in others:
            if gi in weights:
                del weights[gi]
        for gi in index.values():
            weights[gi] = 1.0
    bmesh.update_edit_mesh(obj.data, loop_triangles=False, destructive=False)
    return name


def remove_selected(obj):
    """Take the selected vertices out of every Freeform group."""
    bm, layer = _edit_bmesh(obj)
    groups = [obj.vertex_groups[n].index for n in _all_names(obj)]
    selected = [v for v in bm.verts if v.select]
    if not selected:
        raise UserError("Freeform: no vertex is selected: select the vertices to remove first")
    for v in selected:
        weights = v[layer]
        for gi in groups:
            if gi in weights:
                del weights[gi]
    bmesh.update_edit_mesh(obj.data, loop_triangles=False, destructive=False)


def _all_names(obj):
    names = [n for n, _ in handle_groups(obj)]
    return names + ([SUPPORT] if SUPPORT in obj.vertex_groups else [])


def read(obj):
    """{group name: sorted vertex indices} of the Freeform groups (weight > 0 = member)."""
    names = _all_names(obj)
    by_index = {obj.vertex_groups[n].index: n for n in names}
    members = {n: [] for n in names}
    if obj.mode == 'EDIT':
        bm = bmesh.from_edit_mesh(obj.data)
        bm.verts.index_update()
        layer = bm.verts.layers.deform.active
        if layer is not None:
            for v in bm.verts:
                for gi, w in v[layer].items():
                    if w > 0 and gi in by_index:
                        members[by_index[gi]].append(v.index)
    else:
        for v in obj.data.vertices:
            for g in v.groups:
                if g.weight > 0 and g.group in by_index:
                    members[by_index[g.group]].append(v.index)
    return {n: np.asarray(sorted(ix), dtype=np.int64) for n, ix in members.items()}
