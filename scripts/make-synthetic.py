#!/usr/bin/env python3
"""Make the shipped SYNTHETIC measurement studies/measured/jeffcott-runup-synthetic.csv.

Not a measurement: the model's own run-up (rotorsweep simulate of studies/scenes/jeffcott.toml
ramped 30 -> 38 Hz at 2 Hz/s, recorded from 10 s at 1 kHz with the speed and roll-angle
channels) plus what a laser stand adds:
  - sensor noise: Gaussian, sigma 1.0 um, seeded (numpy default_rng(11));
  - out-of-roundness of the sensor track: 3.0 um cos(2 theta + 0.5) + 1.0 um cos(3 theta - 1.0)
    on every channel (a fixed shape of the surface turning with the roll);
  - speed jitter: the keyphasor pulses are taken from theta plus a seeded random walk of
    0.002 rad rms per revolution (an uneven drive), so the angle rebuilt from the pulses is off
    by that much;
  - the keyphasor as a 0/5 V pulse 0.1 revolution wide (3 samples at 38 Hz), and the speed channel rounded to
    0.01 Hz (a tachometer's resolution).
Usage: python3 scripts/make-synthetic.py ROTORSWEEP_BINARY OUT.csv [FROM_HZ TO_HZ]
FROM_HZ TO_HZ (default 30 38) move the ramp, still at 2 Hz/s after 10 s at FROM_HZ, recorded to
its end: 40 50 makes studies/measured/jeffcott-critical-synthetic.csv, the run-up through the
critical speeds (44.4 Hz horizontal, 44.6 Hz vertical) for the comparison's resonance table.
"""
import subprocess
import sys
import tempfile

import h5py
import numpy as np

if len(sys.argv) not in (3, 5):
    sys.exit("usage: make-synthetic.py ROTORSWEEP_BINARY OUT.csv [FROM_HZ TO_HZ]")
binary, out = sys.argv[1], sys.argv[2]
f0, f1 = (float(v) for v in sys.argv[3:5]) if len(sys.argv) == 5 else (30.0, 38.0)
if not 0.0 < f0 < f1:
    sys.exit(f"make-synthetic.py: a run-up needs 0 < FROM_HZ < TO_HZ, not {f0} {f1}")
t_end = 10.0 + (f1 - f0) / 2.0
with tempfile.TemporaryDirectory() as d:
    h5 = f"{d}/sim.h5"
    subprocess.run(
        [binary, "simulate", "studies/scenes/jeffcott.toml",
         "--set", 'speed.profile="ramp"', "--set", f"speed.from_hz={f0}", "--set", f"speed.to_hz={f1}",
         "--set", "speed.ramp_start_s=10.0", "--set", "speed.rate_hz_per_s=2.0",
         "--set", "simulation.settle_s=10.0", "--set", f"simulation.t_end_s={t_end}",
         "-o", h5], check=True, stdout=subprocess.DEVNULL)
    with h5py.File(h5) as f:
        g = f["jobs/jeffcott"]
        t = g["time"][:]
        theta = g["speed/roll_angle"][:]
        speed = g["speed/hz"][:]
        chans = {f"runout/disk/{d}": g[f"runout/disk/{d}"][:] for d in ("vertical", "horizontal")}
rng = np.random.default_rng(11)
oor = 3.0 * np.cos(2 * theta + 0.5) + 1.0 * np.cos(3 * theta - 1.0)
revs = theta / (2 * np.pi)
walk = np.cumsum(rng.normal(0.0, 0.002, int(revs[-1]) + 2))
jitter = np.interp(revs, np.arange(walk.size), walk)
key = np.where(np.mod(revs + jitter / (2 * np.pi), 1.0) < 0.1, 5.0, 0.0)
cols = {"time_s": t, "keyphasor": key, "speed_hz": np.round(speed, 2)}
for n, x in chans.items():
    cols[n] = x + oor + rng.normal(0.0, 1.0, x.size)
with open(out, "w") as fh:
    fh.write("# SYNTHETIC data, not a measurement: made by scripts/make-synthetic.py (see there:\n")
    fh.write(f"# the Jeffcott model's run-up {f0:g} -> {f1:g} Hz at 2 Hz/s + 1 um noise + track out-of-roundness\n")
    fh.write("# 3 um at 2x, 1 um at 3x + keyphasor jitter 0.002 rad/rev). Runout in um.\n")
    fh.write(",".join(cols) + "\n")
    for i in range(t.size):
        fh.write(",".join(f"{cols[c][i]:.6g}" if c != "time_s" else f"{t[i]:.3f}" for c in cols) + "\n")
