#!/usr/bin/env python3
"""Writes docs/cgal-meshes.md: `freeform info --json` on every libcgal-demo data/meshes/*.off.

Usage: scripts/cgal-mesh-table.py [BUILD_DIR]   (default build/release; run scripts/fetch-data.sh first)
"""
import json
import pathlib
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
cli = root / (sys.argv[1] if len(sys.argv) > 1 else "build/release") / "freeform"
meshes = sorted((root / ".cache/cgal-meshes").glob("*.off"))
rows, loaded, refused, clean = [], 0, 0, 0
for path in meshes:
    header = [t for line in path.read_text(errors="replace").splitlines()[:50]
              for t in line.split("#")[0].split()]
    try:
        i = next(k for k, t in enumerate(header) if "OFF" in t)
        hv, hf = header[i + 1], header[i + 2]
    except (StopIteration, IndexError):
        hv = hf = "?"
    run = subprocess.run([str(cli), "info", "--json", str(path)], capture_output=True, text=True)
    if run.returncode != 0:
        refused += 1
        reason = run.stderr.strip().replace(str(path.parent) + "/", "").replace("|", "\\|")
        rows.append(f"| {path.name} | {hv} | {hf} | refused | | | | {reason} |")
        continue
    loaded += 1
    j = json.loads(run.stdout)
    notes = []
    for key in ("nonmanifold_edges", "nonmanifold_vertices", "inconsistently_oriented_edges", "zero_area_faces",
                "repeated_index_faces", "duplicate_vertices", "unreferenced_vertices"):
        if j[key]:
            notes.append(f"{j[key]} {key.replace('_', ' ')}")
    notes += [w.replace(str(path.parent) + "/", "").replace("|", "\\|") for w in j["warnings"]]
    clean += not notes
    counts_ok = str(j["vertices"]) == hv and (str(j["faces"]) == hf or j["warnings"])
    rows.append(f"| {path.name} | {hv} | {hf} | {j['vertices']} / {j['faces']}{'' if counts_ok else ' (MISMATCH)'} "
                f"| {j['components']} | {j['boundary_loops']} | {j['genus']} | {'; '.join(notes) or 'clean'} |")

out = root / "docs/cgal-meshes.md"
out.write_text(
    "# libcgal-demo meshes\n\n"
    "Every `data/meshes/*.off` of Debian's libcgal-demo (`scripts/fetch-data.sh`), through "
    "`freeform info --json`. Written by `scripts/cgal-mesh-table.py`; the test "
    "`CgalDemoMeshes.EveryOffLoadsWithHeaderCountsOrFailsClearly` checks the same property on every run.\n\n"
    f"{len(meshes)} files: {loaded} loaded, {refused} refused, {clean} without any defect or warning. "
    "Header counts are the file's own `nv nf`; loaded counts are vertices / triangles (polygons are "
    "fan-triangulated, so a polygonal file has more triangles than its header's faces). Components, loops and "
    "genus are of the mesh after splitting non-manifold vertices.\n\n"
    "| file | header V | header F | loaded V / T | components | boundary loops | genus | defects and warnings |\n"
    "|---|---|---|---|---|---|---|---|\n" + "\n".join(rows) + "\n")
print(f"{out}: {len(meshes)} files, {loaded} loaded, {refused} refused, {clean} clean")
