#!/usr/bin/env python3
"""Hostile-input sweep of the freeform CLI (docs/robustness.md).

    scripts/hostile-sweep.py [path/to/freeform]     (default build/release/freeform)

Generates malformed meshes, degenerate and extreme geometry, hostile edit files and output
traps in a scratch folder, runs `freeform info/deform/render` on each and checks what a user
must be able to rely on: no signal (crash), exit codes 0-3 only, a message on every failure,
no output and no temporary left after a failure, finite outputs after a success, inputs never
modified, earlier outputs intact. Prints one line per case family (cases, held) and exits 1 if
any case broke a rule. Runs in about a minute; not part of the default test suite.
"""
import json
import math
import os
import random
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build/release/freeform"))
rng = random.Random(1)
results = {}
failures = []


def grid(n=11, scale=1.0, offset=0.0):
    v = [[i / (n - 1) * scale + offset, j / (n - 1) * scale + offset, offset] for j in range(n) for i in range(n)]
    f = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            f += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
    return v, f


def off_text(v, f):
    return "OFF\n%d %d 0\n" % (len(v), len(f)) + "".join("%r %r %r\n" % tuple(p) for p in v) + \
        "".join("3 %d %d %d\n" % tuple(t) for t in f)


def finite_off(path):
    with open(path) as fh:
        lines = [l for l in fh.read().split("\n") if l and not l.startswith("#")]
    nv = int(lines[1].split()[0])
    return all(math.isfinite(float(x)) for l in lines[2:2 + nv] for x in l.split()[:3])


def run(family, args, work, outputs=(), inputs=(), must_fail=False, expect_finite=True, kill_after=None,
        limit_mb=None, env=None):
    """One case: runs the CLI in `work` (under `ulimit -v limit_mb` if given), checks the rules,
    records held / broken."""
    before = {p: open(p, "rb").read() for p in inputs if os.path.isfile(p)}
    existing = {p: open(p, "rb").read() for p in outputs if os.path.isfile(p)}

    def cap():
        if limit_mb:
            import resource
            resource.setrlimit(resource.RLIMIT_AS, (limit_mb << 20, limit_mb << 20))
    proc = subprocess.Popen([CLI] + args, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE, preexec_fn=cap,
                            env=dict(os.environ, **(env or {})))
    if kill_after is not None:
        time.sleep(kill_after)
        proc.send_signal(signal.SIGTERM)
    try:
        out, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
    rc = proc.returncode
    problems = []
    killed = kill_after is not None and rc == -signal.SIGTERM
    if rc < 0 and not killed:
        problems.append("signal %d" % -rc)
    elif rc > 4:
        problems.append("exit %d" % rc)
    if rc != 0 and not killed and not err.strip():
        problems.append("no message")
    if must_fail and rc == 0:
        problems.append("exit 0 where a refusal was expected")
    if rc == 0 and expect_finite:
        for p in outputs:
            if p.endswith(".off") and os.path.isfile(p) and not finite_off(p):
                problems.append("non-finite output with exit 0")
    if rc != 0:
        for p in outputs:
            if p in existing:
                if open(p, "rb").read() != existing[p]:
                    problems.append("earlier output %s changed" % os.path.basename(p))
            elif os.path.exists(p) and not p.startswith("/dev/"):
                problems.append("partial output %s" % os.path.basename(p))
    for p, data in before.items():
        if open(p, "rb").read() != data:
            problems.append("input %s modified" % os.path.basename(p))
    if any(n.startswith(".") and ".tmp-" in n for n in os.listdir(work)):
        problems.append("temporary left behind")
        for n in os.listdir(work):
            if ".tmp-" in n:
                os.remove(os.path.join(work, n))
    held, total = results.get(family, (0, 0))
    results[family] = (held + (not problems), total + 1)
    if problems:
        failures.append("%s: %s: %s (%s)" % (family, " ".join(args), "; ".join(problems),
                                              err.decode(errors="replace").strip()[-200:]))


def write(path, data):
    with open(path, "wb" if isinstance(data, bytes) else "w") as fh:
        fh.write(data)
    return path


def main():
    work = tempfile.mkdtemp(prefix="freeform-hostile-")
    v, f = grid()
    plane = write(os.path.join(work, "plane.off"), off_text(v, f))
    sel_text = "".join("2\n" if math.hypot(p[0] - .5, p[1] - .5) < .12 else
                       ("1\n" if math.hypot(p[0] - .5, p[1] - .5) < .39 else "0\n") for p in v)
    sel = write(os.path.join(work, "plane.sel"), sel_text)
    lift = write(os.path.join(work, "lift.def"), "1 0 0 0\n0 1 0 0\n0 0 1 0.2\n0 0 0 1\n")
    out = os.path.join(work, "out.off")

    # Malformed meshes: truncations and byte flips of valid files in every format.
    tiny = os.path.join(ROOT, "data/tiny")
    for name in sorted(os.listdir(tiny)):
        data = open(os.path.join(tiny, name), "rb").read()
        ext = os.path.splitext(name)[1]
        for k in range(24):
            b = bytearray(data)
            if k % 3 == 0:
                b = b[:rng.randrange(len(b))]
            else:
                for _ in range(1 + k % 5):
                    b[rng.randrange(len(b))] = rng.randrange(256)
            bad = write(os.path.join(work, "bad" + ext), bytes(b))
            run("malformed meshes", ["info", bad], work)
            run("malformed meshes", ["convert", bad, out], work, outputs=[out], inputs=[bad])
            if os.path.exists(out):
                os.remove(out)

    # Degenerate and extreme geometry through deform (k = 2 and 3).
    cases = []
    for scale in (1e80, 1e-100, 1e-310, 1e150):
        cases.append(("scale %g" % scale, grid(scale=scale)))
    cases.append(("offset 5e6", grid(offset=5e6)))
    vv, ff = grid()
    vv[5 * 11 + 3][1] = vv[4 * 11 + 3][1] + 1e-300
    cases.append(("needle", (vv, ff)))
    vv, ff = grid()
    for k in (5 * 11 + 3, 5 * 11 + 4, 4 * 11 + 3, 4 * 11 + 4):
        vv[k] = list(vv[5 * 11 + 3])
    cases.append(("coincident", (vv, ff)))
    for label, (vv, ff) in cases:
        mesh = write(os.path.join(work, "geom.off"), off_text(vv, ff))
        s = vv[-1][0] - vv[0][0] if label.startswith("scale") else 1.0
        dfile = write(os.path.join(work, "geom.def"), "1 0 0 0\n0 1 0 0\n0 0 1 %r\n0 0 0 1\n" % (0.2 * s))
        for k in (2, 3):
            run("degenerate / extreme geometry", ["deform", mesh, "--sel", sel, "--def", dfile, "--order", str(k),
                                                    "-o", out], work, outputs=[out], inputs=[mesh])
            if os.path.exists(out):
                os.remove(out)
        run("degenerate / extreme geometry", ["render", mesh, "-o", os.path.join(work, "g.png"), "--size", "64x48"],
            work, outputs=[os.path.join(work, "g.png")], inputs=[mesh])

    # Hostile edit files.
    base = {"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.39}},
            "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.12}},
                         "transform": {"translate": [0, 0, 0.2]}}]}
    hostile = [
        {"translate": [1e308, 1e308, 0]}, {"translate": [1e300, 0, 0]}, {"scale": [1e-13, 1, 1]},
        {"scale": [0, 1, 1]}, {"scale": [1e300, 1e300, 1e300]}, {"rotate": {"axis": [0, 0, 1e200], "degrees": 30}},
        {"rotate": {"axis": [0, 0, 3e-300], "degrees": 30}}, {"rotate": {"axis": [0, 0, 0], "degrees": 30}},
        {"rotate": {"axis": [0, 0, 1], "degrees": 1e308}}, {"pivot": [1e308, 0, 0]},
        {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]}, {"translate": "up"},
        {"translate": [0, 0]}, {"bogus": 1},
    ]
    edits = [dict(base, handles=[dict(base["handles"][0], transform=t)]) for t in hostile]
    edits += [dict(base, order=o) for o in (0, 4, -1, 2.5, "2", None)]
    edits += [dict(base, support={"sphere": {"center": [0.5, 0.5, 0], "radius": r}}) for r in (1e-300, 1e300, -1, 0)]
    edits += [dict(base, support={"vertices": list(range(200))}), dict(base, support={"vertices": [-1]}),
              dict(base, support={"geodesic": {"center": [1e200, 0, 0], "radius": 0.3}}),
              dict(base, smoothness={"outer": 7}), dict(base, **{"bad\u0000key": 1}), {"support": {}}, [], "x"]
    for e in edits:
        ef = write(os.path.join(work, "edit.json"), json.dumps(e))
        run("hostile edits", ["deform", plane, "--edit", ef, "-o", out], work, outputs=[out], inputs=[plane, ef])
        if os.path.exists(out):
            os.remove(out)
    sphere_edit = write(os.path.join(work, "edit.json"), json.dumps(dict(base, support={"sphere": {"center": [0, 0, 0], "radius": 9}})))
    ico = os.path.join(work, "ico.off")
    subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, %r); import freeform, numpy; "
                    "m = freeform.make_icosphere(2); freeform.write_mesh(%r, m)" % (os.path.join(ROOT, "build/release/python"), ico)],
                   capture_output=True)
    if os.path.exists(ico):
        run("hostile edits", ["deform", ico, "--edit", sphere_edit, "-o", out], work, outputs=[out], inputs=[ico],
            must_fail=True)

    # NUL bytes: a path cut at the NUL names another file; text after a NUL must not be ignored.
    for text in ('{"support": {"sel": "plane.sel\\u0000.junk", "labels": [1]}}',
                 json.dumps(base) + "\0garbage", json.dumps(base)[:-1] + "\0}"):
        ef = write(os.path.join(work, "edit.json"), text)
        run("NUL bytes", ["deform", plane, "--edit", ef, "-o", out], work, outputs=[out], inputs=[plane, ef],
            must_fail=True)

    # The nonlinear model's scale field: a one-vertex handle scaled about itself moves nothing
    # in linear BCM; scales beyond 1/1000..1000 are refused, those within give finite shapes.
    if os.path.exists(ico):
        lines = [l for l in open(ico).read().split("\n") if l.strip()]
        nv = int(lines[1].split()[0])
        a, b = (int(x) for x in lines[2 + nv].split()[1:3])  # two neighbours: the first face's
        for s_ in (1e6, 1e-6, 1e300, 999.0, 0.002):
            for model in ("nonlinear", "linear"):
                e = {"support": {"vertices": [a, b]}, "allow_unanchored": True, "deformation": model,
                     "handles": [{"region": {"vertices": [b]}, "transform": {"scale": [s_, s_, s_]}}]}
                ef = write(os.path.join(work, "edit.json"), json.dumps(e))
                fail = model == "nonlinear" and not (1e-3 <= s_ <= 1e3)
                run("nonlinear scale field", ["deform", ico, "--edit", ef, "-o", out], work, outputs=[out],
                    inputs=[ico, ef], must_fail=fail)
                if os.path.exists(out):
                    os.remove(out)

    # Memory caps: a k = 3 edit of a 160k-vertex plane under ulimit -v, OpenBLAS with 1 and 2
    # threads: a message and exit 1 (or a result), never a hang, a crash or a broken output.
    big_v, big_f = grid(n=401)
    big = write(os.path.join(work, "big.off"), off_text(big_v, big_f))
    big_edit = write(os.path.join(work, "big.json"), json.dumps(
        {"order": 3, "support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.45}},
         "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.1}}, "transform": {"translate": [0, 0, .2]}}]}))
    earlier = write(os.path.join(work, "earlier.off"), "earlier")
    for limit in (100, 150, 200, 300, 400, 600, 800, 1000):
        for threads in ("1", "2"):
            run("memory caps", ["deform", big, "--edit", big_edit, "-o", earlier], work, outputs=[earlier],
                inputs=[big, big_edit], limit_mb=limit, env={"OPENBLAS_NUM_THREADS": threads})
            write(earlier, "earlier")

    # The Python module's entry points for untrusted data (fuzz/fuzz_python_api.py).
    fuzz = subprocess.run([sys.executable, os.path.join(ROOT, "fuzz", "fuzz_python_api.py"), "--cases", "5000"],
                          capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=os.path.join(ROOT, "build/release/python")))
    results["python api (5000 cases)"] = (int(fuzz.returncode == 0), 1)
    if fuzz.returncode != 0:
        failures.append("python api: exit %d: %s" % (fuzz.returncode, (fuzz.stdout + fuzz.stderr)[-300:]))

    # Output safety: outputs naming inputs, links, devices, missing and read-only folders, kills.
    ef = write(os.path.join(work, "edit.json"), json.dumps(base))
    for target in (plane, ef):
        run("output safety", ["deform", plane, "--edit", ef, "-o", out, "--report", target], work,
            outputs=[out], inputs=[plane, ef], must_fail=True)
    run("output safety", ["deform", plane, "--sel", sel, "--def", lift, "-o", lift], work, inputs=[sel, lift], must_fail=True)
    run("output safety", ["deform", plane, "--sel", sel, "--def", lift, "-o", out, "--report", sel], work,
        outputs=[out], inputs=[sel, lift], must_fail=True)
    real = write(os.path.join(work, "real.off"), "old")
    link = os.path.join(work, "link.off")
    if os.path.lexists(link):
        os.remove(link)
    os.symlink(real, link)
    run("output safety", ["deform", plane, "--edit", ef, "-o", link], work, inputs=[plane, ef])
    if not (os.path.islink(link) and open(real).read().startswith("OFF")):
        failures.append("output safety: symlinked output not written through")
    for dev in ("/dev/null",):
        run("output safety", ["deform", plane, "--edit", ef, "-o", out, "--report", dev], work, inputs=[plane, ef])
        run("output safety", ["render", plane, "-o", dev, "--size", "32x24"], work, inputs=[plane])
        if not os.path.exists(dev) or os.path.isfile(dev):
            failures.append("output safety: %s replaced by a regular file" % dev)
    earlier = write(os.path.join(work, "earlier.off"), "earlier")
    run("output safety", ["deform", plane, "--edit", ef, "-o", earlier, "--report", os.path.join(work, "no", "r.json")],
        work, outputs=[earlier], inputs=[plane, ef], must_fail=True)
    big_v, big_f = grid(n=401)
    big = write(os.path.join(work, "big.off"), off_text(big_v, big_f))
    big_edit = write(os.path.join(work, "big.json"), json.dumps(
        {"order": 3, "support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.45}},
         "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.1}}, "transform": {"translate": [0, 0, .2]}}]}))
    for delay in (0.05, 0.2, 0.5, 1.0, 2.0):
        write(earlier, "earlier")
        run("output safety", ["deform", big, "--edit", big_edit, "-o", earlier, "--report", os.path.join(work, "r.json")],
            work, outputs=[earlier], inputs=[big, big_edit], kill_after=delay)

    # Endless and huge inputs.
    zero = os.path.join(work, "zero.off")
    if not os.path.lexists(zero):
        os.symlink("/dev/zero", zero)
    run("endless / huge inputs", ["info", zero], work, must_fail=True)
    sparse = os.path.join(work, "sparse.off")
    with open(sparse, "wb") as fh:
        fh.truncate(2 << 30)
    run("endless / huge inputs", ["info", sparse], work, must_fail=True)
    os.remove(sparse)
    n = 20000
    fan_v = [[0, 0, 0]] + [[math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), 0] for i in range(n)]
    fan_f = [[0, 1 + i, 1 + (i + 1) % n] for i in range(n)]
    fan = write(os.path.join(work, "fan.off"), off_text(fan_v, fan_f))
    fan_sel = write(os.path.join(work, "fan.sel"), "2\n" + "".join("1\n" if i % 2 == 0 else "0\n" for i in range(n)))
    run("endless / huge inputs", ["deform", fan, "--sel", fan_sel, "--def", lift, "-o", out], work, outputs=[out],
        must_fail=True)

    width = max(len(k) for k in results)
    print("%-*s  cases  held" % (width, "family"))
    for k, (held, total) in results.items():
        print("%-*s  %5d  %4d" % (width, k, total, held))
    for f in failures:
        print("BROKEN:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
