"""The figures of the linearised systems (``/linear/<name>``: of a ``rotorsweep linear -o`` file,
or a study's where its ``[linear]`` table asks): the Campbell diagram (damped whirl frequencies
[Hz] over spin speed [Hz], log decrements), and per system the mode shapes (translation along z
[mm]), the 1× unbalance response [µm, °] as Bode and polar plots, the critical-speed map
(critical speeds [Hz] over support stiffness [N/m]) and the Floquet chart."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.colors import Normalize, TwoSlopeNorm
from matplotlib.figure import Figure
from matplotlib.ticker import ScalarFormatter

import rotorsweep as rp
from rotorsweep import PathLike

from ._common import DIRECTIONS, MAX_SENSORS, figure, significant, unwrap_deg

#: Roll harmonics drawn on the Campbell diagrams (f = k · speed).
HARMONICS = (1, 2, 3, 4)
#: Most linearised systems drawn in the Campbell diagram (one panel each).
MAX_CAMPBELL_PANELS = 4
#: Marker and legend text of each whirl code of ``campbell/whirl`` (1 forward, -1 backward,
#: 0 mixed).
WHIRL_MARKERS = {1: ("^", "forward"), -1: ("v", "backward"), 0: ("o", "mixed")}
#: Lowest lateral modes drawn in the mode-shape figure, at each of two speeds.
MAX_SHAPE_MODES = 4
#: Polar plots label speeds only where the amplitude is at least this share of the largest.
POLAR_LABEL_SHARE = 0.1
#: Lowest critical speeds drawn on the critical-speed map.
MAX_MAP_CRITICALS = 6


def linear_system(g: h5py.Group) -> dict[str, object]:
    """The datasets of one ``/linear/<name>`` group as arrays (text decoded), under their path in
    the group (``campbell/speed_hz``, ``critical_speeds_hz``, …), its attributes
    ``stability_threshold_hz``, ``vertical_hz`` and ``horizontal_hz`` (None when absent), and
    ``unbalance_peaks``: the refined response peaks of the group's ``json`` attribute, a list of
    ``{sensor, critical_hz, speed_hz, major_um, sampled_um, coarse}`` ([] when absent)."""
    data: dict[str, object] = {}

    def visit(name: str, obj: h5py.HLObject) -> None:
        if isinstance(obj, h5py.Dataset):
            v = obj[()]
            data[name] = v.astype(str) if v.dtype.kind == "O" else v

    g.visititems(visit)
    for name in ("stability_threshold_hz", "vertical_hz", "horizontal_hz"):
        value = g.attrs.get(name)
        data[name] = None if value is None else float(value)
    text = g.attrs.get("json")
    if isinstance(text, bytes):
        text = text.decode()
    data["unbalance_peaks"] = (json.loads(text).get("unbalance_peaks") or []) if text else []
    return data


def linear_groups(path: PathLike) -> dict[str, dict[str, object]]:
    """Every ``/linear/<name>`` group with Campbell data, by name, as :func:`linear_system`
    reads it."""
    with h5py.File(path, "r") as f:
        groups = f.get("linear", {})
        return {n: linear_system(groups[n]) for n in groups if "campbell" in groups[n]}


def _over_speed(sys_: dict[str, object]) -> bool:
    """Whether a system was solved at two or more speeds (a curve over speed to draw)."""
    return len(sys_["campbell/speed_hz"]) >= 2


def _log_dec_norm(values: np.ndarray) -> Normalize:
    """Colour scale of log decrements: red for the least damped, centred at zero (white-yellow)
    when some are negative (unstable)."""
    lo, hi = float(np.nanmin(values)), float(np.nanmax(values))
    hi = max(hi, abs(lo) * 1e-3, 1e-12)
    if lo < 0:
        return TwoSlopeNorm(vmin=lo, vcenter=0.0, vmax=hi)
    return Normalize(vmin=0.0, vmax=hi)


def _campbell_panel(ax: Axes, sys_: dict[str, object], title: str) -> object | None:
    """One Campbell panel; returns the scatter of the log decrements (None when not stored)."""
    speed = np.asarray(sys_["campbell/speed_hz"])
    whirl = np.asarray(sys_["campbell/whirl_hz"])
    top = float(speed[-1])
    branch = sys_.get("campbell/branch")
    if branch is not None:
        # One line per Campbell branch (followed by mode shape), not per rank.
        for b in np.unique(branch[branch >= 0]):
            rows, cols = np.nonzero(branch == b)
            order = np.argsort(rows)
            ax.plot(speed[rows[order]], whirl[rows[order], cols[order]], color="0.6", lw=0.8)
    else:
        ax.plot(speed, whirl, color="tab:blue", lw=1)
    scatter = None
    log_dec = sys_.get("campbell/log_dec")
    shown = whirl <= top
    if log_dec is not None and shown.any():
        norm = _log_dec_norm(np.asarray(log_dec)[shown])
        codes = np.asarray(sys_.get("campbell/whirl", np.zeros_like(whirl)))
        grid = np.broadcast_to(speed[:, None], whirl.shape)
        for code, (marker, label) in WHIRL_MARKERS.items():
            pick = shown & (np.rint(codes) == code)
            if pick.any():
                scatter = ax.scatter(
                    grid[pick], whirl[pick], c=log_dec[pick], norm=norm, cmap="RdYlGn",
                    marker=marker, s=18, edgecolors="0.3", linewidths=0.3, zorder=3,
                )
            ax.scatter([], [], marker=marker, color="0.4", label=f"{label} whirl")
    for k in HARMONICS:
        ax.plot(speed, k * speed, color="0.2" if k == 1 else "0.5", lw=1.2 if k == 1 else 0.8,
                ls="-" if k == 1 else ":")
        # Where the line leaves the top edge; 1× leaves at the corner, so its label goes inside.
        if k == 1:
            ax.annotate("1×", (top, top), xytext=(-4, -4), textcoords="offset points",
                        fontsize="small", ha="right", va="top")
        else:
            ax.annotate(f"{k}×", (top / k, top), fontsize="small", ha="center", va="bottom")
    _label_branches(ax, sys_, top)
    crit = np.asarray(sys_.get("critical_speeds_hz", []))
    ax.plot(crit, crit, "o", mfc="none", mec="tab:red", ms=9, mew=1.5, label="critical speeds",
            zorder=4)
    for i, c in enumerate(crit):
        # Alternate below and above the point: neighbouring criticals lie close together; in
        # the right part of the panel, left of the point, clear of the branch labels there.
        right = c > 0.6 * top
        ax.annotate(f"{c:.2f} Hz", (c, c), xytext=(-8 if right else 8, -12 if i % 2 == 0 else 4),
                    textcoords="offset points", fontsize="small", color="tab:red",
                    ha="right" if right else "left")
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel("spin speed [Hz]")
    ax.set_title(title, fontsize="small", pad=14)
    ax.grid(alpha=0.3)
    return scatter


def _branch_names(sys_: dict[str, object]) -> list[tuple[float, str]]:
    """Per Campbell branch in the diagram's range: (its frequency at the top speed [Hz], its
    label): the plane at the lowest speed (vertical / horizontal for the branch nearest, within
    2 %, to the system's first bending frequency in that plane, attributes ``vertical_hz`` and
    ``horizontal_hz``: each plane names one branch, so a near-degenerate pair gets one of each)
    and the whirl at the top speed (forward / backward / mixed). [] without stored branches."""
    speed = np.asarray(sys_["campbell/speed_hz"])
    whirl = np.asarray(sys_["campbell/whirl_hz"])
    branch = sys_.get("campbell/branch")
    codes = sys_.get("campbell/whirl")
    if branch is None:
        return []
    branch = np.asarray(branch)
    top = float(speed[-1])
    ends: dict[int, tuple[float, float, int, int]] = {}
    for b in np.unique(branch[branch >= 0]):
        rows, cols = np.nonzero(branch == b)
        order = np.argsort(rows)
        rows, cols = rows[order], cols[order]
        f0, f1 = whirl[rows[0], cols[0]], whirl[rows[-1], cols[-1]]
        if 0 < f1 <= top and rows[-1] == len(speed) - 1:
            ends[int(b)] = (float(f0), float(f1), int(rows[-1]), int(cols[-1]))
    planes: dict[int, str] = {}
    for attr, name in (("vertical_hz", "vertical"), ("horizontal_hz", "horizontal")):
        f = sys_.get(attr)
        free = [b for b in ends if b not in planes]
        if f is None or not np.isfinite(f) or not free:
            continue
        near = min(free, key=lambda b: abs(ends[b][0] - f))
        if abs(ends[near][0] - f) <= 0.02 * f:
            planes[near] = name
    out = []
    for b, (_, f1, r, c) in ends.items():
        parts = [planes[b]] if b in planes else []
        if codes is not None:
            parts.append(WHIRL_MARKERS[int(np.rint(np.asarray(codes)[r, c]))][1])
        if parts:
            out.append((f1, ", ".join(parts)))
    return sorted(out)


def _label_branches(ax: Axes, sys_: dict[str, object], top: float) -> None:
    """Each branch's label (:func:`_branch_names`) at its right end, inside the axes; labels of
    neighbouring branches alternate above and below their lines."""
    for i, (f, name) in enumerate(_branch_names(sys_)):
        ax.annotate(name, (top, f), xytext=(-4, 3 if i % 2 else -3), textcoords="offset points",
                    ha="right", va="bottom" if i % 2 else "top", fontsize="x-small",
                    color="0.25")


def campbell(systems: list[tuple[str, dict[str, object]]], study: str) -> Figure | None:
    """The Campbell diagram of each linear system (``(title, data)``; at most
    :data:`MAX_CAMPBELL_PANELS` panels): damped whirl frequencies [Hz] over spin speed [Hz], a
    grey line per branch (per rank when the branches are not stored), the 1× line (solid) and
    2×–4× (dotted), the critical speeds; where the log decrements are stored (``rotorsweep
    linear -o``) each mode a marker by whirl (▲ forward, ▼ backward, ● mixed) coloured by its log
    decrement, with a colour bar. None without any system of two or more speeds."""
    systems = [s for s in systems if _over_speed(s[1])][:MAX_CAMPBELL_PANELS]
    if not systems:
        return None
    fig = figure(figsize=(5.2 * len(systems) + 1.6, 5.4))
    axes = fig.subplots(1, len(systems), sharey=True, squeeze=False)[0]
    scatters = [_campbell_panel(ax, data, title) for ax, (title, data) in zip(axes, systems)]
    axes[0].set_ylabel("damped whirl frequency, stationary frame [Hz]")
    axes[0].legend(loc="lower right", fontsize="small")
    shown = [s for s in scatters if s is not None]
    if shown:
        fig.colorbar(shown[0], ax=list(axes), label="log decrement δ (< 0: unstable)")
    fig.suptitle(f"{study}: Campbell diagram on the linearised supports")
    return fig


def study_systems(path: PathLike, names: pd.Series) -> list[tuple[str, dict[str, object]]]:
    """The linear systems of a study in the order of their first job, titled by that job's
    setting ``names`` (no title for a single one)."""
    attrs = rp.job_attrs(path)
    if "linear_id" not in attrs:
        return []
    first = attrs.reset_index().drop_duplicates("linear_id")
    systems = linear_groups(path)
    first = first[first["linear_id"].isin(systems)]
    return [
        (names.get(job["job_id"], job["linear_id"]) if len(first) > 1 else "",
         systems[job["linear_id"]])
        for _, job in first.iterrows()
    ]


def mark_criticals(ax: Axes, sys_: dict[str, object]) -> None:
    """The system's critical speeds [Hz] as dotted red verticals on ``ax``."""
    for c in np.asarray(sys_.get("critical_speeds_hz", [])):
        ax.axvline(c, color="tab:red", lw=0.8, ls=":")


def mode_shapes(sys_: dict[str, object], title: str) -> Figure | None:
    """The lowest :data:`MAX_SHAPE_MODES` lateral modes at the lowest and the highest stored
    speed: horizontal (x) and vertical (y) translation along the rotor, real part (the shape at
    phase 0, largest translation 1) and the envelope ±|X|; None without stored shapes
    (``rotorsweep linear -o --shapes``)."""
    if "shapes/x_re" not in sys_:
        return None
    z = np.asarray(sys_["shapes/node_z_mm"])
    parts = {p: np.asarray(sys_[f"shapes/{p}"]) for p in ("x_re", "x_im", "y_re", "y_im")}
    speed = np.asarray(sys_["campbell/speed_hz"])
    freq, log_dec = np.asarray(sys_["campbell/whirl_hz"]), sys_.get("campbell/log_dec")
    codes = sys_.get("campbell/whirl")
    n = min(MAX_SHAPE_MODES, parts["x_re"].shape[1])
    rows = [0] if len(speed) == 1 else [0, len(speed) - 1]
    fig = figure(figsize=(3.4 * n + 0.5, 2.9 * len(rows) + 1.0))
    axes = fig.subplots(len(rows), n, sharex=True, sharey=True, squeeze=False)
    for r, s in enumerate(rows):
        for k in range(n):
            ax = axes[r, k]
            for d, colour, name in (("x", "tab:blue", "horizontal x"), ("y", "tab:orange",
                                                                       "vertical y")):
                re, im = parts[f"{d}_re"][s, k], parts[f"{d}_im"][s, k]
                size = np.hypot(re, im)
                ax.plot(z, re, color=colour, lw=1.5, marker=".", label=f"{name}, real part")
                ax.fill_between(z, -size, size, color=colour, alpha=0.12, lw=0)
            ax.axhline(0.0, color="black", lw=0.5)
            note = f"{freq[s, k]:.2f} Hz"
            if log_dec is not None:
                note += f", δ {significant(log_dec[s, k], 3)}"
            if codes is not None:
                note += f", {WHIRL_MARKERS[int(np.rint(codes[s, k]))][1]}"
            ax.set_title(f"mode {k + 1} at {speed[s]:g} Hz\n{note}", fontsize="small")
            ax.grid(alpha=0.3)
        axes[r, 0].set_ylabel("translation (largest 1)")
    for ax in axes[-1]:
        ax.set_xlabel("z [mm]")
    axes[0, 0].legend(fontsize="x-small", loc="lower center")
    fig.suptitle(f"{title}: lateral mode shapes (shaded: envelope ±|X| of the orbit)")
    return fig


def responses(sys_: dict[str, object]) -> list[str]:
    """The sensors with an unbalance response, at most :data:`MAX_SENSORS`."""
    names = [k.split("/")[1] for k in sys_ if k.startswith("unbalance_response/")
             and k.endswith("/vertical/amplitude_um")]
    return names[:MAX_SENSORS]


def peak_label(peak: dict[str, object]) -> str:
    """A refined response peak as its figure label: ``peak 6468 µm at 27.25 Hz``, with ``(sweep
    misses it)`` when it is ``coarse`` (the sampled curve stays more than 1 % below it)."""
    text = f"peak {float(peak['major_um']):.4g} µm at {float(peak['speed_hz']):.2f} Hz"
    return text + " (sweep misses it)" if peak["coarse"] else text


def bode(sys_: dict[str, object], title: str) -> Figure | None:
    """Bode plot of the 1× unbalance response per sensor (one column each): amplitude [µm] and
    phase [°] (unwrapped, against roll angle 0; none at zero amplitude) over spin speed [Hz],
    vertical and horizontal and the orbit's major semi-axis (grey), each sample a dot, the
    critical speeds dotted; the refined peaks of the major semi-axis (``unbalance_peaks``) marked
    and labelled with their amplitude and speed (★; ✕ and "sweep misses it" where the sampled
    curve stays more than 1 % below the peak: the curve between the samples is not the response
    there); None without a stored response."""
    sensors = responses(sys_)
    if not sensors or not _over_speed(sys_):
        return None
    speed = np.asarray(sys_["campbell/speed_hz"])
    fig = figure(figsize=(4.6 * len(sensors) + 0.6, 6.2))
    axes = fig.subplots(2, len(sensors), sharex=True, squeeze=False)
    peaks = list(sys_.get("unbalance_peaks", []))
    missed = 0
    for c, sensor in enumerate(sensors):
        for d, colour in zip(DIRECTIONS, ("tab:orange", "tab:blue")):
            key = f"unbalance_response/{sensor}/{d}"
            amp = np.asarray(sys_[f"{key}/amplitude_um"])
            # Without amplitude (at standstill) the phase means nothing: left out, and the rest
            # unwrapped.
            phase = unwrap_deg(np.where(amp > 0, np.asarray(sys_[f"{key}/phase_deg"]), np.nan))
            axes[0, c].plot(speed, amp, color=colour, marker=".", ms=3, label=d)
            axes[1, c].plot(speed, phase, color=colour, marker=".", ms=3, label=d)
        major = sys_.get(f"unbalance_response/{sensor}/major_um")
        if major is not None:
            axes[0, c].plot(speed, np.asarray(major), color="0.55", lw=0.8, marker=".", ms=2,
                            label="orbit major semi-axis", zorder=1)
        mine = sorted((p for p in peaks if p["sensor"] == sensor),
                      key=lambda p: -float(p["major_um"]))
        missed += sum(bool(p["coarse"]) for p in mine)
        for i, p in enumerate(mine):
            x, y = float(p["speed_hz"]), float(p["major_um"])
            coarse = bool(p["coarse"])
            axes[0, c].plot([x], [y], marker="X" if coarse else "*", ms=9, ls="none",
                            color="tab:purple" if coarse else "black", zorder=5)
            # Largest first, each label a line lower: close peaks' labels do not overlap.
            axes[0, c].annotate(peak_label(p), (x, y), xytext=(7, -2 - 11 * i),
                                textcoords="offset points", fontsize="x-small", va="top",
                                color="tab:purple" if coarse else "black")
        if mine:
            # Room above the highest peak for its marker and label.
            axes[0, c].set_ylim(top=1.12 * max(float(p["major_um"]) for p in mine))
        axes[0, c].set_title(sensor)
        axes[1, c].set_xlabel("spin speed [Hz]")
        for ax in axes[:, c]:
            mark_criticals(ax, sys_)
            ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("1× amplitude [µm]")
    axes[1, 0].set_ylabel("1× phase [°] (x = A cos(θ + φ))")
    axes[0, 0].plot([], [], color="tab:red", lw=0.8, ls=":", label="critical speeds")
    if not all(p["coarse"] for p in peaks):
        axes[0, 0].plot([], [], marker="*", ls="none", color="black",
                        label="refined peak (major semi-axis)")
    if missed:
        axes[0, 0].plot([], [], marker="X", ls="none", color="tab:purple",
                        label="peak the sweep misses")
    # In the phase panel's free middle: the amplitude panel's is the peaks' labels'.
    axes[1, 0].legend(*axes[0, 0].get_legend_handles_labels(), fontsize="small",
                      loc="center right")
    note = (f"\nthe {speed.size}-speed sweep misses {missed} peak{'s' if missed > 1 else ''}: "
            "the curve between samples is not the response there" if missed else "")
    fig.suptitle(f"{title}: unbalance response (Bode){note}")
    return fig


def polar(sys_: dict[str, object], title: str) -> Figure | None:
    """Polar plot of the 1× unbalance response per sensor: amplitude [µm] at angle φ [°] (phase
    against roll angle 0) as the speed rises, vertical and horizontal, a few speeds labelled;
    None without a stored response over two or more speeds."""
    sensors = responses(sys_)
    if not sensors or not _over_speed(sys_):
        return None
    speed = np.asarray(sys_["campbell/speed_hz"])
    fig = figure(figsize=(4.6 * len(sensors) + 0.6, 5.2))
    for c, sensor in enumerate(sensors):
        ax = fig.add_subplot(1, len(sensors), c + 1, projection="polar")
        for d, colour in zip(DIRECTIONS, ("tab:orange", "tab:blue")):
            key = f"unbalance_response/{sensor}/{d}"
            amp = np.asarray(sys_[f"{key}/amplitude_um"])
            phi = np.radians(np.asarray(sys_[f"{key}/phase_deg"]))
            ax.plot(phi, amp, color=colour, marker=".", ms=3, label=d)
            # A few speeds labelled, among the points away from the centre (where they crowd).
            big = np.flatnonzero(amp >= POLAR_LABEL_SHARE * np.max(amp, initial=0.0))
            for i in big[np.unique(np.linspace(0, len(big) - 1, 6).round().astype(int))]:
                ax.annotate(f"{speed[i]:g}", (phi[i], amp[i]), fontsize="x-small", color=colour)
        ax.set_title(f"{sensor} [µm]; labels: speed [Hz]", fontsize="small", pad=16)
        ax.tick_params(labelsize="x-small")
    fig.axes[0].legend(fontsize="small", loc="lower left", bbox_to_anchor=(-0.15, -0.12))
    fig.suptitle(f"{title}: unbalance response (polar, phase against roll angle 0)")
    return fig


def critical_map(sys_: dict[str, object], title: str) -> Figure | None:
    """The undamped critical-speed map: the lowest :data:`MAX_MAP_CRITICALS` critical speeds
    [Hz] against the (isotropic) support stiffness [N/m], log–log, the actual supports' kx and
    ky marked; None without a stored map."""
    if "critical_map/critical_speeds_hz" not in sys_:
        return None
    k = np.asarray(sys_["critical_map/stiffness_n_per_m"])
    crit = np.asarray(sys_["critical_map/critical_speeds_hz"])[:, :MAX_MAP_CRITICALS]
    fig = figure(figsize=(8.5, 5.5))
    ax = fig.subplots()
    for j in range(crit.shape[1]):
        ax.plot(k, crit[:, j], color=f"C{j}", marker=".", label=f"critical {j + 1}")
    nodes = list(sys_.get("critical_map/support_nodes", []))
    actual = {}
    for d, key in (("kx", "actual_kx_n_per_m"), ("ky", "actual_ky_n_per_m")):
        for node, value in zip(nodes, np.asarray(sys_.get(f"critical_map/{key}", []))):
            if value > 0:
                actual.setdefault(float(value), []).append(f"{node} {d}")
    for i, (value, who) in enumerate(sorted(actual.items())):
        ax.axvline(value, color="0.3", ls="--", lw=0.9)
        ax.annotate(f"actual: {', '.join(who)}\n{value:.3g} N/m", (value, 0.02 + 0.1 * i),
                    xycoords=("data", "axes fraction"), xytext=(4, 0),
                    textcoords="offset points", fontsize="x-small")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("support stiffness, every support isotropic [N/m]")
    ax.set_ylabel("undamped critical speed [Hz]")
    ax.grid(alpha=0.3, which="both")
    ax.yaxis.set_major_formatter(ScalarFormatter())
    ax.yaxis.set_minor_formatter(ScalarFormatter())
    ax.tick_params(axis="y", which="minor", labelsize="x-small")
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(f"{title}: critical-speed map")
    return fig


def floquet(sys_: dict[str, object], title: str) -> Figure | None:
    """The Floquet stability chart: −ln max|μ| of the monodromy over one revolution (a log
    decrement per revolution; < 0 unstable) over spin speed [Hz], symmetric-log scale, the
    unstable ranges shaded and the constant-coefficient stability threshold dashed; None without
    Floquet data at two or more speeds."""
    if "floquet/growth_per_rev" not in sys_:
        return None
    speed = np.asarray(sys_["floquet/speed_hz"])
    if speed.size < 2:
        return None
    decay = -np.asarray(sys_["floquet/growth_per_rev"])
    ranges = np.asarray(sys_.get("floquet/unstable_ranges_hz", np.zeros((0, 2)))).reshape(-1, 2)
    fig = figure(figsize=(7.5, 5))
    ax = fig.subplots()
    ax.plot(speed, decay, color="tab:blue", marker=".", label="−ln max|μ| per revolution")
    for i, (a, b) in enumerate(ranges):
        ax.axvspan(a, b, color="tab:red", alpha=0.2,
                   label="Floquet-unstable" if i == 0 else None)
    threshold = sys_.get("stability_threshold_hz")
    if threshold is not None:
        ax.axvline(threshold, color="0.2", ls="--", lw=1,
                   label=f"threshold of the damped modes {threshold:.2f} Hz")
    ax.axhline(0.0, color="black", lw=0.8)
    small = np.abs(decay[decay != 0])
    ax.set_yscale("symlog", linthresh=float(np.min(small)) if small.size else 1e-6)
    ax.set_xlabel("spin speed [Hz]")
    ax.set_ylabel("−ln max|μ| per revolution (< 0: unstable)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    state = (f"unstable {', '.join(f'{a:.2f}–{b:.2f} Hz' for a, b in ranges)}"
             if len(ranges) else "stable at every speed")
    ax.set_title(f"{title}: Floquet stability over one revolution (body frame)\n{state}",
                 fontsize="medium")
    return fig


def linear_figures(systems: dict[str, dict[str, object]]) -> list[tuple[str, Figure | None]]:
    """The per-system figures (mode shapes, Bode, polar, critical-speed map, Floquet) of each
    system, named ``<figure>[-<system>].png`` (the suffix only with several systems)."""
    out: list[tuple[str, str, Figure]] = []
    for what in (mode_shapes, bode, polar, critical_map, floquet):
        for name, data in systems.items():
            fig = what(data, name)
            if fig is not None:
                out.append((what.__name__, name, fig))
    counts = pd.Series([w for w, _, _ in out]).value_counts()
    return [(f"{w}-{n}.png" if counts[w] > 1 else f"{w}.png", fig) for w, n, fig in out]
