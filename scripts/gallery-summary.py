#!/usr/bin/env python3
"""Summarizes bench_gallery's JSON: per method the totals of folded edges and collapsed faces,
the mean over cases of the support's compressive strain and halved area, unconverged runs, the slowest run, the
iterations, the runs over issue 37's time goal (a solve over 1 s at up to 10,000 free vertices, over 10 s above),
the same totals per edit kind (bends, twists, pulls, several limbs, drags, pushes, scaled handles, turns in place, bumps, dents), and per Freeform method the cases worse than the peer
(CGAL ARAP) by more than 2 folded edges or 2 collapsed faces, worst first, and its unconverged runs, then
those over the time goal, slowest first. --peer-from takes the
peer's runs from an earlier gallery JSON (the same cases: each case's vertex, support and handle
counts must match), so that a quick loop without the peer (`bench_gallery --no-peer`) is still
compared with it (data/gallery/ stores them: scripts/gallery-quick.sh). --save-peer
writes the peer's runs of gallery.json alone to a file for --peer-from.
    scripts/gallery-summary.py gallery.json [--peer "CGAL ARAP"] [--peer-from peer.json] [--save-peer out.json]"""
import json
import os
import sys

# Issue 37's time goal for a solve: 1 s up to this many free vertices, 10 s above.
SMALL_FREE, SMALL_MS, LARGE_MS = 10_000, 1_000.0, 10_000.0
# The edit kinds of bench_gallery's case names (CASE-limbN-twist137, CASE-two-limbs-bend112, ...;
# drag and push with --drags, grow and shrink with --scales, turn with --turns, bump and dent with
# --bumps), in the order the breakdown lists them; a name with none is "other".
KINDS = ("two-limbs", "bend", "twist", "pull", "drag", "push", "grow", "shrink", "turn", "bump", "dent")


def edit_kind(case: str) -> str:
    """The kind of edit a case name says (the first of KINDS it holds), else "other"."""
    return next((k for k in KINDS if f"-{k}" in case or case.startswith(k)), "other")


def print_kinds(cases: list, methods: list[str]) -> None:
    """Per edit kind, each method's folded edges / collapsed faces summed over the kind's cases."""
    totals: dict[str, dict[str, list[int]]] = {}
    for case in cases:
        kind = totals.setdefault(edit_kind(case["case"]), {})
        for r in case["runs"]:
            if "error" not in r:
                t = kind.setdefault(r["method"], [0, 0, 0])
                t[0] += 1
                t[1] += r["folded_edges"]
                t[2] += r["collapsed_faces"]
    print("\nBy edit kind (cases: folded edges / collapsed faces)\n")
    print("| kind | " + " | ".join(methods) + " |")
    print("|---|" + "---|" * len(methods))
    for kind in [k for k in KINDS + ("other",) if k in totals]:
        cells = [f"{t[0]}: {t[1]} / {t[2]}" if (t := totals[kind].get(m)) else "" for m in methods]
        print(f"| {kind} | " + " | ".join(cells) + " |")


def print_late_runs(methods: dict, peer: str) -> None:
    """Per method but the peer, its unconverged runs and then those over the time goal by name, slowest first."""
    for name, m in methods.items():
        if name == peer or not m["late"]:
            continue
        print(f"\n{name}: runs unconverged or over the time goal (free vertices, iterations, solve)")
        for ms, case, free, iterations, converged in sorted(m["late"], key=lambda t: (t[4], -t[0]))[:8]:
            print(f"  {case}: {free} free, {iterations} iterations, {ms:.0f} ms" +
                  ("" if converged else ", not converged"))


def take_option(args: list[str], flag: str) -> str | None:
    """Removes `flag VALUE` from args and returns VALUE (None if absent); exits 2 without a value."""
    if flag not in args:
        return None
    i = args.index(flag)
    if i + 1 >= len(args):
        print(f"gallery-summary: {flag} needs a value", file=sys.stderr)
        sys.exit(2)
    value = args[i + 1]
    del args[i:i + 2]
    return value


def read_json(path: str) -> list:
    with open(path, encoding="utf-8") as f:
        try:
            return json.load(f)
        except ValueError as e:
            raise ValueError(f"{path}: not gallery JSON ({e})") from e


# What makes two gallery cases of the same name the same edit, as far as the JSON tells.
CASE_KEYS = ("vertices", "support", "handles")


def take_peer_runs(cases: list, earlier: list, peer: str, peer_from: str) -> str | None:
    """Replaces each case's peer runs by those of the same case in `earlier`; the error, if any."""
    earlier_of = {c["case"]: c for c in earlier}
    for case in cases:
        old = earlier_of.get(case["case"])
        runs = [r for r in old["runs"] if r["method"] == peer] if old else []
        if old is None or not runs:
            return f"{peer_from} has no {peer} run of case {case['case']}"
        for key in CASE_KEYS:
            if key in old and key in case and old[key] != case[key]:
                return (f"{peer_from}: case {case['case']} has {key} {old[key]} there and {case[key]} here: "
                        "not the same edit (run the peer again)")
        case["runs"] = [r for r in case["runs"] if r["method"] != peer] + runs
    return None


def save_peer_runs(cases: list, peer: str, path: str) -> None:
    """Writes the cases with their peer runs alone (atomically): a file for --peer-from."""
    kept = [{**{k: v for k, v in c.items() if k != "runs"}, "runs": [r for r in c["runs"] if r["method"] == peer]}
            for c in cases]
    missing = [c["case"] for c in kept if not c["runs"]]
    if missing:
        raise ValueError(f"no {peer} run of case {missing[0]} to save")
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(kept, f, indent=0, sort_keys=True)
        f.write("\n")
    os.replace(tmp, path)


def main() -> int:
    args = sys.argv[1:]
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    peer = take_option(args, "--peer") or "CGAL ARAP"
    peer_from = take_option(args, "--peer-from")
    save_peer = take_option(args, "--save-peer")
    if len(args) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        cases = read_json(args[0])
        earlier = read_json(peer_from) if peer_from else []
    except (OSError, ValueError) as e:
        print(f"gallery-summary: {e}", file=sys.stderr)
        return 1
    if peer_from and (error := take_peer_runs(cases, earlier, peer, peer_from)):
        print(f"gallery-summary: {error}", file=sys.stderr)
        return 1
    if save_peer:
        try:
            save_peer_runs(cases, peer, save_peer)
        except (OSError, ValueError) as e:
            print(f"gallery-summary: {save_peer}: {e}", file=sys.stderr)
            return 1
    methods: dict[str, dict] = {}
    for case in cases:
        runs = {r["method"]: r for r in case["runs"]}
        ref = runs.get(peer)
        for name, r in runs.items():
            m = methods.setdefault(name, {"folds": 0, "collapsed": 0, "compression": 0.0, "halved": 0.0,
                                          "errors": 0, "unconverged": 0, "max_ms": 0.0, "worse": [], "cases": 0,
                                          "iterations": 0, "slow": 0, "late": []})
            m["cases"] += 1
            if "error" in r:
                m["errors"] += 1
                continue
            m["folds"] += r["folded_edges"]
            m["collapsed"] += r["collapsed_faces"]
            m["compression"] += r.get("compression", 0.0)
            m["halved"] += r.get("halved_area", 0.0)
            m["unconverged"] += 0 if r.get("converged", True) else 1
            m["max_ms"] = max(m["max_ms"], r.get("precompute_ms", 0) + r.get("solve_ms", 0))
            m["iterations"] += r.get("iterations", 0)
            slow = "solve_ms" in r and r["solve_ms"] > (SMALL_MS if r.get("free", 0) <= SMALL_FREE else LARGE_MS)
            m["slow"] += 1 if slow else 0
            if slow or not r.get("converged", True):
                m["late"].append((r.get("solve_ms", 0.0), case["case"], r.get("free", 0), r.get("iterations", 0),
                                  r.get("converged", True)))
            if ref and "error" not in ref and name != peer:
                df = r["folded_edges"] - ref["folded_edges"]
                dc = r["collapsed_faces"] - ref["collapsed_faces"]
                if df > 2 or dc > 2 or (ref["folded_edges"] == 0 and r["folded_edges"] > 0):
                    m["worse"].append((max(df, dc), case["case"], r["folded_edges"], ref["folded_edges"],
                                       r["collapsed_faces"], ref["collapsed_faces"]))
    print(f"| method | cases | folded edges | collapsed faces | mean compression | mean halved area | "
          f"worse than {peer} | unconverged | errors | slowest (ms) | iterations | over the time goal |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, m in methods.items():
        worse = "" if name == peer else str(len(m["worse"]))
        ok = max(m["cases"] - m["errors"], 1)
        print(f"| {name} | {m['cases']} | {m['folds']} | {m['collapsed']} | {m['compression'] / ok:.4f} | "
              f"{m['halved'] / ok:.4f} | {worse} | {m['unconverged']} | {m['errors']} | {m['max_ms']:.0f} | "
              f"{m['iterations']} | {m['slow']} |")
    print_kinds(cases, list(methods))
    for name, m in methods.items():
        if not m["worse"]:
            continue
        print(f"\n{name}: worst cases against {peer} (folds ours/peer, collapsed ours/peer)")
        for _, case, f, pf, c, pc in sorted(m["worse"], reverse=True)[:8]:
            print(f"  {case}: {f}/{pf}, {c}/{pc}")
    print_late_runs(methods, peer)
    return 0


if __name__ == "__main__":
    sys.exit(main())
