"""A slimmer reference roll, built in Python: its modes and Campbell diagram beside the original's.

    python python/examples/campbell_variant.py [-o DIR] [--diameter-mm 300] [--speeds 0:60:31]

The reference roll (studies/scenes/reference-roll.toml, a Ø320 mm shell) with a Ø300 mm shell,
the balancing masses moved to a radius inside both shells, is run through ``rotorsweep modes``
and ``rotorsweep linear`` from Python (:mod:`rotorsweep`: the scene's file with ``--set``
arguments; the file itself is not changed). Written to DIR (default ``campbell-variant`` in the
current folder):

* ``campbell-variant.png``: the damped whirl frequencies [Hz] over spin speed [Hz] of the lateral modes
  below 1.6 × the top speed, the variant in colour (▲ forward, ▼ backward whirl), the reference roll in grey,
  the 1× line (whirl = spin) and the variant's critical speeds;
* ``slim-roll.toml``: the variant as a scene file (the reference roll's comments kept; its
  thickness map named relative to DIR), which ``rotorsweep`` takes like any scene.

It prints the variant's first supported frequencies and critical speeds. Needs the binary
(``$ROTORSWEEP_BIN``, ``rotorsweep`` on PATH, or the checkout's target/release/rotorsweep) and
``pip install "./python[figures]"`` (matplotlib).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import rotorsweep as rs

ROOT = Path(__file__).resolve().parents[2]
#: The scene the variant is made of.
REFERENCE = ROOT / "studies" / "scenes" / "reference-roll.toml"
#: The variant's shell outer diameter [mm] (the reference roll's is 320).
DIAMETER_MM = 300.0
#: Balancing radius [mm]: inside the material of both shells (the reference roll's 160 mm is its
#: outer surface, outside a Ø300 mm shell).
BALANCING_RADIUS_MM = 145.0
#: Spin speeds START:STOP:COUNT [Hz] of the Campbell diagram.
SPEEDS = "0:60:31"
#: The diagram's frequency range, as a multiple of the top speed: the modes below it are drawn.
FREQ_RANGE = 1.6


def variant(diameter_mm: float = DIAMETER_MM) -> rs.Scene:
    """The reference roll with a shell of ``diameter_mm`` (both keys set, then checked once)."""
    scene = rs.Scene(REFERENCE)
    scene.update(
        {
            "name": "slim-roll",
            "roll.balancing.radius_mm": BALANCING_RADIUS_MM,
            "roll.shell.outer_diameter_mm": diameter_mm,
        }
    )
    return scene


def plot(reference: Any, slim: Any, title: str, path: Path) -> Path:
    """The Campbell diagram of ``slim`` over ``reference`` (Datasets of :func:`rotorsweep.campbell`)
    as a PNG at ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.5), layout="constrained")
    speed = slim.speed_hz.values
    top = FREQ_RANGE * speed[-1]
    for k in range(reference.sizes["mode"]):
        f = reference.whirl_hz.isel(mode=k)
        if float(f.min()) < top:
            ax.plot(reference.speed_hz, f, color="0.6", lw=2.5, alpha=0.6,
                    label="reference roll (Ø320 mm)" if k == 0 else None)
    colours = plt.get_cmap("tab10")
    for k in range(slim.sizes["mode"]):
        f = slim.whirl_hz.isel(mode=k)
        if float(f.min()) >= top:
            continue
        ax.plot(slim.speed_hz, f, color=colours(k), lw=1.5, label=f"lateral mode {k}")
        for code, marker in ((1, "^"), (-1, "v")):
            at = (slim.whirl.isel(mode=k) == code).values
            ax.plot(speed[at], f.values[at], marker, color=colours(k), ms=4, ls="none")
    ax.plot(speed, speed, "k--", lw=1, label="1× (whirl = spin)")
    ax.plot([], [], "k^", ms=4, ls="none", label="forward whirl")
    ax.plot([], [], "kv", ms=4, ls="none", label="backward whirl")
    if "critical_speed_hz" in slim:
        for c in slim.critical_speed_hz.values:
            if c <= speed[-1]:
                ax.axvline(c, color="red", ls=":", lw=1)
                ax.annotate(f"critical {c:.1f} Hz", (c, top * 0.98), rotation=90, va="top", ha="right",
                            color="red", fontsize=8)
    ax.set(xlabel="spin speed [Hz]", ylabel="damped whirl frequency [Hz]", title=title,
           xlim=(speed[0], speed[-1]), ylim=(0, top))
    ax.legend(fontsize=8, loc="upper left", framealpha=0.9)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(out_dir: Path, diameter_mm: float = DIAMETER_MM, speeds: str = SPEEDS) -> dict[str, Any]:
    """Runs the example into ``out_dir``; returns the variant scene, its modes table
    (:func:`rotorsweep.modes`), both Campbell datasets (:func:`rotorsweep.linear`) and the paths
    written."""
    out_dir.mkdir(parents=True, exist_ok=True)
    slim = variant(diameter_mm)
    modes = rs.modes(slim)
    campbell = rs.linear(slim, speeds=speeds)
    reference = rs.linear(rs.Scene(REFERENCE), speeds=speeds)
    png = plot(reference, campbell, f"Campbell diagram: the reference roll with a Ø{diameter_mm:g} mm shell",
               out_dir / "campbell-variant.png")
    saved = slim.save(out_dir / "slim-roll.toml", overwrite=True)
    return {"scene": slim, "modes": modes, "campbell": campbell, "reference": reference, "png": png, "saved": saved}


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--out", type=Path, default=Path("campbell-variant"), help="output folder")
    ap.add_argument("--diameter-mm", type=float, default=DIAMETER_MM, help="the shell's outer diameter [mm]")
    ap.add_argument("--speeds", default=SPEEDS, help="spin speeds START:STOP:COUNT [Hz]")
    a = ap.parse_args()
    r = main(a.out, a.diameter_mm, a.speeds)
    sup = r["modes"].attrs["supported_hz"]
    print(f"{r['scene'].name}: {r['modes'].attrs.get('mass_kg', float('nan')):.1f} kg")
    print("supported at standstill [Hz]: vertical", ", ".join(f"{f:.2f}" for f in sup["vertical"][:4]),
          "; horizontal", ", ".join(f"{f:.2f}" for f in sup["horizontal"][:4]))
    crit = r["campbell"].get("critical_speed_hz")
    if crit is not None:
        print("critical speeds [Hz]:", ", ".join(f"{c:.2f}" for c in crit.values))
    print(r["png"])
    print(r["saved"])
