"""The package as users get it (docs/python.md): typed (a stub checked against the module by
mypy's stubtest, which fails when a binding has no stub), documented, mypy --strict clean
examples and docs snippets, and, installed from the wheel, self-contained."""
import ast
import os
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

import freeform
from conftest import REPO

PACKAGE = pathlib.Path(freeform.__file__).parent
ALLOWLIST = REPO / "python" / "stubtest-allowlist.txt"
INSTALLED = os.environ.get("FREEFORM_INSTALLED") == "1"
# Static checks need mypy (scripts/bootstrap.sh installs it); they say nothing about memory
# safety, so the sanitizer run leaves them out.
needs_mypy = pytest.mark.skipif(
    os.environ.get("FREEFORM_PYTHON_SANITIZED") == "1" or shutil.which("mypy") is None and
    os.environ.get("FREEFORM_REQUIRE_DATA") != "1", reason="static checks: not under the sanitizers, or no mypy")


def mypy_env(package_parent):
    """mypy finds an installed package itself (PEP 561) and refuses site-packages in MYPYPATH."""
    if INSTALLED and package_parent == PACKAGE.parent:
        return dict(os.environ)
    return dict(os.environ, MYPYPATH=str(package_parent), PYTHONPATH=str(package_parent))


def stubtest(package_parent, cwd):
    env = mypy_env(package_parent)
    return subprocess.run([sys.executable, "-m", "mypy.stubtest", "freeform", "--allowlist", str(ALLOWLIST)],
                          capture_output=True, text=True, cwd=cwd, env=env, timeout=300)


@needs_mypy
def test_the_stub_matches_the_module(tmp_path):
    run = stubtest(PACKAGE.parent, tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr


@needs_mypy
def test_stubtest_fails_when_a_binding_has_no_stub(tmp_path):
    copy = tmp_path / "pkg" / "freeform"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    stub = copy / "__init__.pyi"
    text = stub.read_text()
    assert "    def n_edges(self) -> int: ..." in text
    stub.write_text(text.replace("    @property\n    def n_edges(self) -> int: ...\n", ""))
    run = stubtest(copy.parent, tmp_path)
    assert run.returncode != 0 and "freeform.Mesh.n_edges" in run.stdout, run.stdout


def test_every_public_name_of_the_compiled_module_is_exported():
    compiled = {n for n in dir(freeform._freeform) if not n.startswith("_")}
    assert compiled <= set(freeform.__all__), compiled - set(freeform.__all__)
    assert set(freeform.__all__) <= set(dir(freeform))


def public_members():
    for name in freeform.__all__:
        obj = getattr(freeform, name)
        yield name, obj
        if isinstance(obj, type) and not issubclass(obj, (dict, BaseException)):
            for member, value in vars(obj).items():
                if not member.startswith("_"):
                    yield f"{name}.{member}", value


def test_every_public_function_class_and_property_has_a_docstring():
    missing = [name for name, obj in public_members() if not (getattr(obj, "__doc__", None) or "").strip()]
    assert not missing, missing


def test_array_docstrings_name_shapes_and_dtypes():
    # Everything that takes or returns an array says which.
    arrays = ["Mesh.__init__", "Mesh.vertices", "Mesh.faces", "Edit.support", "EditSolver.evaluate",
              "EditSolver.evaluate_into", "EditSolver.touched", "EditSolver.transforms", "EditSolver.handle_centroid",
              "deform", "write_mesh"]
    docs = dict(public_members())
    docs["Mesh.__init__"] = freeform.Mesh.__init__
    for name in arrays:
        doc = docs[name].__doc__
        assert re.search(r"float64|int64|integer|real", doc) and re.search(r"\(\w+, \d\)|\(\w+,\)|\d x \d|n x 3|m x 3", doc), \
            f"{name}: {doc}"


def test_the_version_is_the_projects():
    cmake = (REPO / "CMakeLists.txt").read_text()
    assert re.search(r"project\(freeform VERSION (\S+)", cmake).group(1) == freeform.__version__


def python_snippets(markdown):
    return re.findall(r"```python\n(.*?)```", markdown, flags=re.S)


@needs_mypy
def test_examples_and_docs_snippets_pass_mypy_strict(tmp_path):
    files = sorted((REPO / "examples").glob("*.py"))
    assert files, "examples/*.py"
    snippets = python_snippets((REPO / "docs" / "python.md").read_text())
    assert len(snippets) >= 3
    for i, code in enumerate(snippets):
        (tmp_path / f"python_md_{i}.py").write_text(code)
        files.append(tmp_path / f"python_md_{i}.py")
    env = mypy_env(PACKAGE.parent)
    run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--cache-dir", str(tmp_path / "cache"),
                          *map(str, files)], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr


@pytest.mark.parametrize("example", sorted(p.name for p in (REPO / "examples").glob("*.py")))
def test_examples_run(example, tmp_path):
    from conftest import MESH_DIR, require_file
    require_file(MESH_DIR / "armadillo.off")
    env = dict(os.environ, FREEFORM_MESH_DIR=str(MESH_DIR), FREEFORM_OUT_DIR=str(tmp_path))
    run = subprocess.run([sys.executable, str(REPO / "examples" / example)], capture_output=True, text=True,
                         env=env, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr


# --- the installed wheel (scripts/test-wheel.sh sets FREEFORM_INSTALLED=1) ---
installed_only = pytest.mark.skipif(not INSTALLED, reason="checks the package installed from the wheel")
ALLOWED = re.compile(r"^(linux-vdso|ld-linux-x86-64|libc|libm|libmvec|libpthread|libdl|librt|libstdc\+\+|libgcc_s)\.so")


@installed_only
def test_installed_from_the_wheel_not_the_build_tree():
    assert pathlib.Path(sys.prefix) in PACKAGE.parents and PACKAGE.parent.name == "site-packages", PACKAGE
    assert REPO not in PACKAGE.parents, PACKAGE


@installed_only
def test_the_module_needs_only_glibc_libstdcxx_libgcc_and_the_wheel():
    module = next(PACKAGE.glob("_freeform*.so"))
    ldd = subprocess.run(["ldd", str(module)], capture_output=True, text=True, check=True).stdout
    outside = []
    for line in ldd.splitlines():
        name = os.path.basename(line.split()[0])
        path = line.split("=>")[1].split("(")[0].strip() if "=>" in line else ""
        if not ALLOWED.match(name) and not path.startswith(str(PACKAGE / "_libs")):
            outside.append(line.strip())
    assert not outside, ldd


@installed_only
def test_the_demo_runs_where_debians_suitesparse_metis_and_openblas_are_hidden(tmp_path):
    from conftest import DATA_DIR, MESH_DIR, require_file
    mesh = require_file(MESH_DIR / "armadillo.off")
    code = f"""
import re, freeform
mesh = freeform.read_mesh({str(mesh)!r})
edit = freeform.read_edit({str(DATA_DIR / "edits" / "armadillo.json")!r}, mesh)
V = freeform.EditSolver(mesh, edit).evaluate()
freeform.write_mesh({str(tmp_path / "out.off")!r}, V, mesh.faces)
maps = open("/proc/self/maps").read()
print(sorted(set(re.findall(r"/\\S*/lib(?:cholmod|umfpack|metis|openblas)\\S*", maps))))
"""
    run = subprocess.run([str(REPO / "scripts" / "without-system-libs.sh"), sys.executable, "-c", code],
                         capture_output=True, text=True, cwd=tmp_path, timeout=300)
    if run.returncode == 77:
        pytest.skip(run.stderr.strip())
    assert run.returncode == 0, run.stdout + run.stderr
    loaded = ast.literal_eval(run.stdout.strip().splitlines()[-1])
    assert loaded and all(path.startswith(str(PACKAGE / "_libs")) for path in loaded), loaded
    assert (tmp_path / "out.off").stat().st_size > 0
