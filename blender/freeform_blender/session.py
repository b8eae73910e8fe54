"""The precomputed state of one mesh object: its rest shape, the EditSolver (built in a
background thread), the current handle transforms and the shapes it wrote (so Blender's undo,
which restores positions only, also restores the transforms that made them)."""

import hashlib
import json
import threading

import numpy as np

from . import mesh_data, regions
from .native import UserError, failure, require

_sessions = {}  # object name -> Session


def shape_hash(points):
    return hashlib.blake2b(np.ascontiguousarray(points, dtype=np.float32).tobytes(), digest_size=16).digest()


def settings_dict(obj):
    """The object's settings (properties.py) as the settings keys of an edit file
    (docs/edit-format.md): the one place the add-on maps its properties to the library's."""
    s = obj.freeform
    k = int(s.order)
    return {
        "order": k,
        "smoothness": {"outer": min(s.outer, k - 1.0), "inner": min(s.inner, k - 1.0)},
        "anisotropic": bool(s.anisotropic),
        "multiresolution": bool(s.multiresolution),
        "deformation": s.deformation.lower(),
        "nonlinear": {"preserve_volume": bool(s.preserve_volume)},
    }


def edit_dict(obj, members, transforms, tris):
    """The edit-file schema (docs/edit-format.md) for the object's groups and settings, and the
    movable handles' names in the edit's order. Loose
    vertices (in no face) are left out: nothing could move them, they stay where they are."""
    in_faces = np.zeros(len(obj.data.vertices), dtype=bool)
    in_faces[tris.ravel()] = True
    members = {n: ix[in_faces[ix]] for n, ix in members.items()}
    support = members.get(regions.SUPPORT, np.empty(0, dtype=np.int64))
    handles, movable_names = [], []
    for name, movable in regions.handle_groups(obj):
        ix = members.get(name)
        if ix is None or len(ix) == 0:
            continue
        entry = {"region": {"vertices": ix}}
        if movable:
            entry["transform"] = {"matrix": transforms.get(name, np.eye(4))}
            movable_names.append(name)
        else:
            entry["fixed"] = True
        handles.append(entry)
    if len(support) == 0:
        raise UserError(f"Freeform: the support of '{obj.name}' is empty: select the vertices that may move "
                        "and press Assign to Support")
    if not movable_names:
        raise UserError(f"Freeform: '{obj.name}' has no movable handle: select vertices inside the support "
                        "and press New Handle")
    return dict(settings_dict(obj), support={"vertices": support}, handles=handles), movable_names


class Session:
    def __init__(self, name, key, rest, tris, movable, transforms):
        self.name = name  # the object's, for messages
        self.key = key
        self.rest = rest
        self.tris = tris
        self.movable = movable  # movable handle names, in the solver's order
        self.transforms = {n: transforms.get(n, np.eye(4)) for n in movable}
        self.history = {shape_hash(rest): {}}  # shapes written -> the transforms that made them
        self.solver = None
        self.error = None
        self.progress = ("assembly", 0.0)
        self.cancelled = False
        self.thread = None
        self.out = rest.copy()
        self.write_all = False  # next write: every row (the regions changed on a moved shape)

    # precompute ---------------------------------------------------------------------------
    def start(self, mesh, edit, background):
        def progress(stage, done):
            if self.cancelled:
                raise KeyboardInterrupt("cancelled")
            self.progress = (stage, done)

        def run():
            try:
                self.solver = require().EditSolver(mesh, edit, progress=progress)
            except BaseException as error:  # reported on the main thread
                self.error = error

        if background:
            self.thread = threading.Thread(target=run, name="freeform-precompute", daemon=True)
            self.thread.start()
        else:
            run()

    @property
    def running(self):
        return self.thread is not None and self.thread.is_alive()

    def wait(self):
        if self.thread is not None:
            self.thread.join()
        if self.error is not None:
            raise UserError(f"Freeform: '{self.name}': {self.error}")
        return self.solver

    # frames ------------------------------------------------------------------------------
    def transform_list(self, transforms=None):
        t = transforms if transforms is not None else self.transforms
        return [t[n] for n in self.movable]

    def pivot(self, name, transforms=None):
        t = (transforms or self.transforms)[name]
        c = self.solver.handle_centroid(self.movable.index(name))
        return t[:3, :3] @ c + t[:3, 3]

    def evaluate(self, transforms=None):
        self.solver.evaluate_into(self.out, self.transform_list(transforms))
        return self.out

    def write(self, obj, transforms):
        """Show the result of `transforms` and remember it (the end of an operation: an undo step)."""
        self.evaluate(transforms)
        self.show(obj, transforms)
        self.remember()

    def drag(self, obj, transforms):
        """A mouse move: shows at once the nonlinear model's newest iterate, moved by linear BCM's
        change to `transforms` (its iterations run on a worker thread; solver.frame); returns
        whether the shown shape is settled (linear: always). Not remembered: only the shape an
        operation ends with becomes an undo step."""
        state = self.solver.frame(self.out, self.transform_list(transforms))
        self.show(obj, transforms)
        return state["settled"]

    def refine(self, obj):
        """Shows the worker's newer iterate, if any (a timer tick); returns whether settled."""
        state = self.solver.frame(self.out, self.transform_list())
        if state["written"]:
            self.show(obj, self.transforms)
        return state["settled"]

    def show(self, obj, transforms):
        mesh_data.write_positions(obj, self.out, None if self.write_all else self.solver.touched)
        self.write_all = False
        self.transforms = {n: m.copy() for n, m in transforms.items()}

    def remember(self):
        """The shape shown now was made by the current transforms (found again after an undo)."""
        self.history[shape_hash(self.out)] = self.transforms


def _key(obj, members, tris):
    digest = hashlib.blake2b(tris.tobytes(), digest_size=16)
    for name in sorted(members):
        digest.update(name.encode() + b"\0" + members[name].tobytes())
    return (len(obj.data.vertices), digest.digest(), json.dumps(settings_dict(obj), sort_keys=True))


def get(obj):
    return _sessions.get(obj.name)


def forget(obj):
    s = _sessions.pop(obj.name, None)
    if s is not None:
        s.cancelled = True


def forget_all():
    """Cancel and wait: a thread still inside the C++ solver must not outlive the add-on."""
    for s in _sessions.values():
        s.cancelled = True
    for s in _sessions.values():
        if s.thread is not None:
            s.thread.join()
    _sessions.clear()


def prepare(obj, background=False):
    """The object's session, up to date with its groups, settings and shape; precomputes (in a
    thread when background) when something changed. A shape that no Freeform edit produced
    (another tool moved vertices) becomes the new rest shape."""
    ff = require()
    current = mesh_data.positions(obj)
    tris = mesh_data.triangles(obj)
    if len(tris) == 0:
        raise UserError(f"Freeform: '{obj.name}' has no faces")
    members = regions.read(obj)
    key = _key(obj, members, tris)
    old = _sessions.get(obj.name)
    known = old.history.get(shape_hash(current)) if old is not None else None
    if old is not None and old.key == key and known is not None and old.error is None:
        old.transforms = {n: known.get(n, np.eye(4)) for n in old.movable}
        return old
    rest, transforms = (old.rest, known) if known is not None and len(old.rest) == len(current) else (current, {})
    edit_data, movable = edit_dict(obj, members, {}, tris)
    try:
        mesh = ff.Mesh(rest, tris)
        edit = ff.Edit.from_dict(edit_data, mesh, name=obj.name)
    except ff.Error as error:
        raise failure(obj, error) from None
    if old is not None:
        old.cancelled = True
    s = Session(obj.name, key, rest, tris, movable, transforms)
    if known is not None:
        s.history.update(old.history)  # same rest: the shapes it made stay recognizable
        s.write_all = True
    _sessions[obj.name] = s
    s.start(mesh, edit, background)
    return s
