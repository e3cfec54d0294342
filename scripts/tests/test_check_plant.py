"""scripts/check-plant.py: the exported linear plant (.h5, .npz and MATLAB .mat) read by
python-control and scipy.signal has the frequency response of `rotorsweep linear`'s unbalance
response at the plant's speed (relative difference <= 1e-6), the .npz and .mat plants equal the
.h5 one bit for bit (scipy.io.loadmat reads the .mat), and a tolerance it misses fails the
script.

The binary is $ROTORSWEEP_BIN (scripts/python-test sets it), else target/release/rotorsweep.
"""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "check-plant.py"
SCENE = ROOT / "studies" / "scenes" / "reference-roll.toml"


def check(*extra: str) -> subprocess.CompletedProcess[str]:
    # check-plant.py itself takes $ROTORSWEEP_BIN, else target/release/rotorsweep.
    env = dict(os.environ)
    return subprocess.run(
        [sys.executable, str(SCRIPT), str(SCENE), "--speed-hz", "12", *extra],
        capture_output=True, text=True, timeout=600, env=env,
    )


def test_plant_matches_the_unbalance_response_in_python_control_and_scipy():
    p = check()
    assert p.returncode == 0, p.stdout + p.stderr
    lines = p.stdout.splitlines()
    # 3 files x 2 tools x 3 sensors x 2 directions, then the summary.
    assert sum(", linear " in l for l in lines) == 36
    assert sum("equal the .h5 plant's bit for bit" in l for l in lines) == 2
    worst = float(lines[-1].split()[3])
    assert worst <= 1e-6


def test_a_tolerance_below_the_difference_fails():
    p = check("--tolerance", "0")
    assert p.returncode == 1, p.stdout + p.stderr
