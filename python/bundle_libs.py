#!/usr/bin/env python3
"""Makes the compiled `freeform` module self-contained (docs/python.md, "The wheel").

    bundle_libs.py PACKAGE_DIR/_freeform.*.so

Copies every shared library the module needs, directly or through another one, except glibc,
libstdc++ and libgcc, into PACKAGE_DIR/_libs, as auditwheel does: each copy gets its own
SONAME (`libcholmod.so.3` -> `libcholmod-freeform.so.3`) and every reference to it is
renamed, so a process that already loaded the system's library of the same name (numpy's BLAS,
Blender's OpenBLAS) still uses the bundled one; the run paths are `$ORIGIN`-relative. The BLAS and
LAPACK that OpenBLAS's alternatives provide are answered by libopenblas itself (it exports
both), which saves their 8 MB copies. Needs `ldd` and `patchelf`.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys

# Part of every Linux the module runs on (the C library and the compiler's C++ runtime).
SYSTEM = re.compile(r"^(linux-vdso|ld-linux|libc|libm|libmvec|libpthread|libdl|librt|libutil|libresolv"
                    r"|libstdc\+\+|libgcc_s)\.so")
LIB_DIR = "_libs"


def dependencies(path):
    """{soname: resolved file} of everything `path` loads, transitively (ldd)."""
    out = subprocess.run(["ldd", str(path)], check=True, capture_output=True, text=True).stdout
    found = {}
    for line in out.splitlines():
        m = re.match(r"\s*(\S+) => (\S+) \(", line)
        if m:
            found[m.group(1)] = m.group(2)
        elif "not found" in line:
            raise SystemExit(f"bundle_libs: {path}: {line.strip()}")
    return found


def needed(path):
    return subprocess.run(["patchelf", "--print-needed", str(path)], check=True, capture_output=True,
                          text=True).stdout.split()


def bundled_name(soname):
    stem, _, version = soname.partition(".so")
    return f"{stem}-freeform.so{version}"


def patchelf(*args):
    subprocess.run(["patchelf", *map(str, args)], check=True)


def bundle(module):
    module = pathlib.Path(module)
    libs = module.parent / LIB_DIR
    shutil.rmtree(libs, ignore_errors=True)
    libs.mkdir()
    deps = {name: pathlib.Path(path).resolve() for name, path in dependencies(module).items()
            if not SYSTEM.match(name)}
    # OpenBLAS's BLAS and LAPACK shims: libopenblas exports both interfaces.
    alias = {}
    openblas = next((n for n in deps if n.startswith("libopenblas")), None)
    for shim in ("libblas.so.3", "liblapack.so.3"):
        if openblas and shim in deps and openblas in needed(deps[shim]):
            alias[shim] = bundled_name(openblas)
            del deps[shim]
    rename = {name: bundled_name(name) for name in deps} | alias
    copies = []
    for name, source in sorted(deps.items()):
        target = libs / rename[name]
        shutil.copyfile(source, target)
        os.chmod(target, 0o755)
        patchelf("--set-soname", target.name, target)
        copies.append(target)
    for obj in [module, *copies]:
        for old in needed(obj):
            if old in rename:
                patchelf("--replace-needed", old, rename[old], obj)
        patchelf("--set-rpath", "$ORIGIN" if obj.parent == libs else f"$ORIGIN/{LIB_DIR}", obj)
    return copies


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    copies = bundle(sys.argv[1])
    size = sum(p.stat().st_size for p in copies)
    print(f"bundle_libs: {len(copies)} libraries, {size / 1e6:.1f} MB, in {pathlib.Path(sys.argv[1]).parent / LIB_DIR}")


if __name__ == "__main__":
    main()
