"""A short, seeded run of the Python API fuzz target (fuzz/fuzz_python_api.py) in a child
process: a crash (a list nested 100,000 deep used to kill the interpreter) is a signal there,
an undocumented exception its exit 1. scripts/run-fuzzers.sh python runs it for longer."""
import os
import subprocess
import sys

from conftest import REPO


def test_python_api_fuzz_target_survives():
    result = subprocess.run([sys.executable, "-X", "dev", str(REPO / "fuzz" / "fuzz_python_api.py"), "--cases", "1500",
                             "--seed", "39"], capture_output=True, text=True, timeout=300, env=dict(os.environ))
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert "1500 cases, 0 unexpected exceptions" in result.stdout
