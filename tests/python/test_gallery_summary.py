"""scripts/gallery-summary.py on a hand-made gallery JSON: the totals, the cases worse than the peer
and the runs over issue 37's time goal (1 s up to 10,000 free vertices, 10 s above)."""
import json
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "gallery-summary.py"


def run(free, folds, collapsed, iterations, solve_ms, method="freeform k2"):
    return {"method": method, "free": free, "folded_edges": folds, "collapsed_faces": collapsed,
            "iterations": iterations, "solve_ms": solve_ms, "precompute_ms": 10.0, "converged": True}


def script(tmp_path, cases, *options) -> subprocess.CompletedProcess:
    """The script run on `cases` written as a gallery JSON."""
    path = tmp_path / "run.json"
    path.write_text(json.dumps(cases))
    return subprocess.run([sys.executable, str(SCRIPT), str(path), *options], capture_output=True, text=True)


def summarize(tmp_path, cases) -> str:
    """The script's output for `cases`; it must succeed."""
    out = script(tmp_path, cases)
    assert out.returncode == 0, out.stderr
    return out.stdout


def table(text: str) -> dict:
    """The rows of the first markdown table in text, by their first cell."""
    return {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
            for line in text.split("\n\n")[0].splitlines() if line.startswith("| ") and "---" not in line}


def test_totals_worse_cases_and_time_goal(tmp_path):
    cases = [
        # 3 more folded edges than the peer: worse; 1.5 s at 5,000 free: over the goal.
        {"case": "small", "runs": [run(5000, 5, 0, 10, 1500.0), run(5000, 2, 0, 0, 9000.0, "CGAL ARAP")]},
        # Better than the peer; 9 s at 20,000 free: within the goal.
        {"case": "large", "runs": [run(20000, 0, 1, 7, 9000.0), run(20000, 3, 3, 0, 5.0, "CGAL ARAP")]},
        # 11 s at 40,000 free: over; as many collapsed faces as the peer plus 2: not worse.
        {"case": "larger", "runs": [run(40000, 0, 4, 20, 11000.0), run(40000, 0, 2, 0, 5.0, "CGAL ARAP")]},
    ]
    out = summarize(tmp_path, cases)
    rows = table(out)
    ours = rows["freeform k2"]
    assert ours[0:3] == ["3", "5", "5"]  # cases, folded edges, collapsed faces
    assert ours[5] == "1"  # worse than the peer: "small" only
    assert ours[-2:] == ["37", "2"]  # iterations, over the time goal
    assert rows["CGAL ARAP"][-1] == "1"  # its 9 s at 5,000 free
    assert "small: 5/2, 0/0" in out
    # The runs over the goal by name, slowest first; the peer's are not listed.
    late = out.split("freeform k2: runs unconverged or over the time goal")[1].splitlines()[1:]
    assert late == ["  larger: 40000 free, 20 iterations, 11000 ms", "  small: 5000 free, 10 iterations, 1500 ms"]
    assert "CGAL ARAP: runs" not in out


def test_unconverged_runs_are_listed_by_name(tmp_path):
    capped = {**run(300, 1, 0, 500, 400.0), "converged": False}
    out = summarize(tmp_path, [{"case": "engine-limb1-bend87", "runs": [capped]},
                               {"case": "slow", "runs": [run(3000, 0, 0, 90, 1200.0)]},
                               {"case": "fast", "runs": [run(300, 0, 0, 20, 30.0)]}])
    assert table(out)["freeform k2"][6] == "1"  # unconverged
    # Unconverged first, though faster than the run over the time goal.
    late = out.split("runs unconverged or over the time goal")[1].splitlines()[1:]
    assert late == ["  engine-limb1-bend87: 300 free, 500 iterations, 400 ms, not converged",
                    "  slow: 3000 free, 90 iterations, 1200 ms"]


def test_totals_by_edit_kind(tmp_path):
    cases = [
        {"case": "cow-limb0-twist137", "runs": [run(100, 4, 1, 5, 10.0), run(100, 6, 2, 0, 5.0, "CGAL ARAP")]},
        {"case": "cow-limb1-twist90", "runs": [run(100, 1, 0, 5, 10.0), run(100, 0, 3, 0, 5.0, "CGAL ARAP")]},
        # Two limbs bent: its own kind, not a bend.
        {"case": "cow-two-limbs-bend112", "runs": [run(200, 7, 2, 5, 10.0), run(200, 9, 9, 0, 5.0, "CGAL ARAP")]},
        {"case": "bar", "runs": [run(50, 0, 0, 5, 10.0), run(50, 1, 0, 0, 5.0, "CGAL ARAP")]},
        # bench_gallery --drags: handles moved without turning.
        {"case": "cow-limb0-drag71", "runs": [run(100, 0, 1, 5, 10.0), run(100, 2, 2, 0, 5.0, "CGAL ARAP")]},
        {"case": "cow-limb0-push30", "runs": [run(100, 3, 4, 5, 10.0), run(100, 1, 0, 0, 5.0, "CGAL ARAP")]},
        # --scales, --turns and --bumps: scaled or turned handles, discs pulled out or pushed in.
        {"case": "cow-limb0-grow150", "runs": [run(100, 1, 0, 5, 10.0), run(100, 2, 0, 0, 5.0, "CGAL ARAP")]},
        {"case": "cow-limb0-shrink60", "runs": [run(100, 0, 2, 5, 10.0), run(100, 0, 3, 0, 5.0, "CGAL ARAP")]},
        {"case": "cow-limb1-turn90", "runs": [run(100, 2, 1, 5, 10.0), run(100, 3, 3, 0, 5.0, "CGAL ARAP")]},
        {"case": "cow-bump0-80", "runs": [run(100, 1, 1, 5, 10.0), run(100, 4, 0, 0, 5.0, "CGAL ARAP")]},
        {"case": "cow-dent1-30", "runs": [run(100, 0, 0, 5, 10.0), run(100, 0, 1, 0, 5.0, "CGAL ARAP")]},
    ]
    kinds = table(summarize(tmp_path, cases).split("By edit kind (cases: folded edges / collapsed faces)\n\n")[1])
    assert kinds["twist"] == ["2: 5 / 1", "2: 6 / 5"]
    assert kinds["two-limbs"] == ["1: 7 / 2", "1: 9 / 9"]
    assert kinds["drag"] == ["1: 0 / 1", "1: 2 / 2"]
    assert kinds["push"] == ["1: 3 / 4", "1: 1 / 0"]
    assert kinds["other"] == ["1: 0 / 0", "1: 1 / 0"]
    assert "bend" not in kinds and "pull" not in kinds
    assert kinds["grow"] == ["1: 1 / 0", "1: 2 / 0"]
    assert kinds["shrink"] == ["1: 0 / 2", "1: 0 / 3"]
    assert kinds["turn"] == ["1: 2 / 1", "1: 3 / 3"]
    assert kinds["bump"] == ["1: 1 / 1", "1: 4 / 0"]
    assert kinds["dent"] == ["1: 0 / 0", "1: 0 / 1"]
    assert list(kinds)[-8:] == ["drag", "push", "grow", "shrink", "turn", "bump", "dent", "other"]  # in the order of KINDS


def test_saved_peer_runs_compare_like_the_run_itself(tmp_path):
    case = {"case": "cow-limb0-twist137", "vertices": 3000, "support": 120, "handles": 1}
    ours, peer = run(100, 5, 1, 5, 10.0), run(100, 2, 1, 0, 5.0, "CGAL ARAP")
    with_peer = script(tmp_path, [{**case, "runs": [ours, peer]}], "--save-peer", str(tmp_path / "peer.json"))
    assert with_peer.returncode == 0, with_peer.stderr
    saved = json.loads((tmp_path / "peer.json").read_text())
    assert [r["method"] for r in saved[0]["runs"]] == ["CGAL ARAP"] and saved[0]["support"] == 120
    without_peer = script(tmp_path, [{**case, "runs": [ours]}], "--peer-from", str(tmp_path / "peer.json"))
    assert without_peer.returncode == 0, without_peer.stderr
    assert table(without_peer.stdout) == table(with_peer.stdout)
    assert "cow-limb0-twist137: 5/2, 1/1" in without_peer.stdout


def test_peer_runs_of_another_edit_are_refused(tmp_path):
    case = {"case": "cow-limb0-twist137", "vertices": 3000, "support": 120, "handles": 1}
    (tmp_path / "peer.json").write_text(json.dumps([{**case, "support": 140, "runs": [run(100, 2, 1, 0, 5.0, "CGAL ARAP")]}]))
    out = script(tmp_path, [{**case, "runs": [run(100, 5, 1, 5, 10.0)]}], "--peer-from", str(tmp_path / "peer.json"))
    assert out.returncode == 1 and out.stdout == ""
    assert "case cow-limb0-twist137 has support 140 there and 120 here" in out.stderr
