"""Edit from files and dicts: the same schema and messages, to_dict round trips."""
import copy
import json

import numpy as np
import pytest

import freeform
from conftest import plane_edit_dict


def test_from_dict_equals_read_edit(tmp_path, plane):
    path = tmp_path / "edit.json"
    path.write_text(json.dumps(plane_edit_dict()))
    from_file = freeform.read_edit(path, plane)
    from_dict = freeform.Edit.from_dict(plane_edit_dict(), plane)
    assert from_file.to_dict() == from_dict.to_dict()
    assert np.array_equal(freeform.deform(plane, from_file), freeform.deform(plane, from_dict))


def test_properties(plane_edit):
    assert (plane_edit.order, plane_edit.n_handles, plane_edit.n_movable) == (2, 2, 1)
    assert plane_edit.multiresolution
    assert plane_edit.support.dtype == np.int64 and len(plane_edit.support) > 50
    assert "order 2" in repr(plane_edit)


def test_to_dict_round_trip_deforms_bit_for_bit(plane, plane_edit):
    d = plane_edit.to_dict()
    assert d["handles"][0]["transform"].keys() == {"matrix"} or "translate" in d["handles"][0]["transform"]
    assert d["handles"][1]["fixed"] is True
    json.dumps(d)  # plain Python data
    again = freeform.Edit.from_dict(d, plane)
    assert again.to_dict() == d
    assert np.array_equal(freeform.deform(plane, again), freeform.deform(plane, plane_edit))


def test_deformations_lists_the_models_edit_files_accept(plane):
    """freeform.DEFORMATIONS (what the Blender add-on offers) are the names the edit format takes."""
    assert freeform.DEFORMATIONS == ("linear", "nonlinear")
    for name in freeform.DEFORMATIONS:
        d = dict(plane_edit_dict(), deformation=name)
        assert freeform.Edit.from_dict(d, plane).to_dict()["deformation"] == name
    with pytest.raises(freeform.Error, match='"deformation" must be one of "linear", "nonlinear"'):
        freeform.Edit.from_dict(dict(plane_edit_dict(), deformation="arap"), plane)


def test_every_settings_key_survives_from_dict_to_dict(plane):
    """Each settings key of an edit file (docs/edit-format.md), away from its default, comes
    back from Edit.from_dict -> to_dict unchanged (the library reads and writes them)."""
    d = plane_edit_dict()
    settings = {"order": 3, "smoothness": {"outer": 0.5, "inner": 1.25}, "anisotropic": True,
                "multiresolution": False, "deformation": "nonlinear",
                "nonlinear": {"max_iterations": 250, "tolerance": 3e-05, "preserve_volume": False},
                "allow_unanchored": True}
    d.update(settings)
    back = freeform.Edit.from_dict(d, plane).to_dict()
    for key, value in settings.items():
        assert back[key] == value, key


def test_write_edit(tmp_path, plane, plane_edit):
    freeform.write_edit(tmp_path / "e.json", plane_edit)
    assert freeform.read_edit(tmp_path / "e.json", plane).to_dict() == plane_edit.to_dict()


def test_numpy_values_in_dicts(plane):
    d = plane_edit_dict()
    d["order"] = np.int64(3)
    d["support"]["sphere"]["center"] = np.array([0.5, 0.5, 0.0])
    d["handles"][1]["region"]["vertices"] = np.array([80], dtype=np.uint32)
    d["handles"][0]["transform"]["translate"] = (np.float32(0), 0, np.float64(0.2))
    e = freeform.Edit.from_dict(d, plane)
    assert e.order == 3 and e.to_dict()["handles"][1]["region"]["vertices"] == [80]


BAD_EDITS = [  # (change to the plane edit, expected message after "NAME: ")
    (lambda d: d["handles"][0].update(transfrom={}), 'unknown key "handles[0].transfrom"'),
    (lambda d: d.update(order=5), '"order" must be 1 (membrane), 2 (thin plate) or 3'),
    (lambda d: d.update(order="two"), '"order" must be'),
    (lambda d: d.pop("support"), '"support"'),
    (lambda d: d["handles"][1]["region"].update(vertices=[100000]), "100000"),
    (lambda d: d.update(smoothness={"outer": 3}), '"smoothness.outer" must be in [0, 1] for order 2'),
    (lambda d: d["handles"][0].update(transform={"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]}),
     '"handles[0].transform.matrix" is singular'),
    (lambda d: d["handles"][0].update(transform={"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]}),
     "the last row must be 0 0 0 1"),
    (lambda d: d.update(handles={}), '"handles"'),
]


@pytest.mark.parametrize("change,expected", BAD_EDITS)
def test_dict_errors_are_the_edit_file_errors(tmp_path, plane, change, expected):
    d = copy.deepcopy(plane_edit_dict())
    change(d)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(d))
    with pytest.raises(freeform.Error) as from_file:
        freeform.read_edit(path, plane)
    with pytest.raises(freeform.Error) as from_dict:
        freeform.Edit.from_dict(d, plane)
    file_message, dict_message = str(from_file.value), str(from_dict.value)
    assert file_message.startswith(f"{path}: ") and dict_message.startswith("edit: ")
    assert file_message[len(f"{path}: "):] == dict_message[len("edit: "):]
    assert expected in dict_message
    assert isinstance(from_dict.value, ValueError) and type(from_dict.value) is freeform.Error


def test_dict_error_names(plane):
    d = plane_edit_dict()
    d["support"]["sphere"]["radius"] = float("nan")
    with pytest.raises(freeform.Error, match=r'^my edit: "support.sphere.radius" must be finite$'):
        freeform.Edit.from_dict(d, plane, name="my edit")
    with pytest.raises(TypeError, match=r'keys must be strings, got 1 in "support"'):
        freeform.Edit.from_dict({"support": {1: 2}}, plane)
    with pytest.raises(TypeError, match=r'cannot convert <class \'set\'> to JSON at "handles\[0\].region"'):
        freeform.Edit.from_dict({"support": {"vertices": [1]}, "handles": [{"region": {3}}]}, plane)
    with pytest.raises(freeform.Error, match="the edit must be a JSON object, got an array"):
        freeform.Edit.from_dict([1, 2], plane)


def test_sel_paths_relative_to_base_dir(tmp_path, plane):
    (tmp_path / "s.sel").write_text("".join("1\n" if i < 40 else "0\n" for i in range(plane.n_vertices)))
    d = {"support": {"sel": "s.sel", "labels": [1]}}
    assert len(freeform.Edit.from_dict(d, plane, base_dir=tmp_path).support) == 40
    with pytest.raises(freeform.IoError):
        freeform.Edit.from_dict(d, plane, base_dir=tmp_path / "elsewhere")


def test_smoothness_segments_from_dicts(plane):
    """A C0 stretch of the outer boundary: kept through to_dict, changes the result, and a
    segment that selects no band vertex is an error naming it."""
    d = plane_edit_dict(order=3)
    d["multiresolution"] = False
    uniform = freeform.deform(plane, freeform.Edit.from_dict(d, plane))
    d["smoothness"] = {"segments": [{"region": {"sphere": {"center": [0.95, 0.5, 0], "radius": 0.3}},
                                     "value": np.float64(0.0)}]}
    edit = freeform.Edit.from_dict(d, plane)
    back = edit.to_dict()
    (segment,) = back["smoothness"]["segments"]
    assert segment["value"] == 0.0 and len(segment["region"]["vertices"]) > 5
    creased = freeform.deform(plane, edit)
    assert np.abs(creased - uniform).max() > 1e-3
    assert np.array_equal(freeform.deform(plane, freeform.Edit.from_dict(back, plane)), creased)
    d["smoothness"]["segments"].append({"region": {"sphere": {"center": [4 / 12, 0.5, 0], "radius": 0.02}}, "value": 1})  # a free vertex
    with pytest.raises(freeform.Error, match=r"smoothness\.segments\[1\]\.region.* selects no constrained vertex"):
        freeform.Edit.from_dict(d, plane)
