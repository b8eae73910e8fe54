"""The bundled `freeform` module (built by scripts/blender-addon.sh into this package)."""

try:
    from . import freeform as ff  # noqa: F401  (the freeform package, with its libraries in freeform/_libs)
    IMPORT_ERROR = None
except ImportError as error:  # a zip without the module, or built for another Python
    ff = None
    IMPORT_ERROR = (f"Freeform: the compiled module could not be loaded ({error}); build the add-on with "
                    "scripts/blender-addon.sh for this Blender's Python")


class UserError(Exception):
    """A problem the user can fix: reported as a Blender error message, never a traceback."""


def require():
    if ff is None:
        raise UserError(IMPORT_ERROR)
    return ff


def failure(obj, error):
    """A library error as a message naming the object, with Blender's way to fix it."""
    text = str(error)
    if ff is not None and isinstance(error, ff.TopologyError):
        text = text.split("; rerun with repair")[0] + (
            " (Select > Select All by Trait > Non Manifold shows them; fix with Mesh > Clean Up or by hand)")
    return UserError(f"Freeform: '{obj.name}': {text}")
