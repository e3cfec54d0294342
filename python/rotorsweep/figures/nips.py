"""The figures of a machine's nips, from the report's ``nips`` table (Rust computes the static
loads and the line amplitudes, ``src/report/tables/nips.rs``; this module only draws them).

In: the report's JSON document (``rotorsweep report FILE --format json``), its table ``nips``:
per job and nip a ``total`` row and one row per segment with ``z_mm`` and ``length_mm`` [mm],
``static_n`` [N], ``line_load_kn_per_m`` [kN/m] and ``amplitude_<k>x_n`` [N] per order k of
the first roll's speed, and per roll of the nip (side ``a``, ``b``) ``roll_<side>`` (its name) and
``amplitude_<side>_<k>x_n`` [N] per order k of that roll's own speed; each job's speed [Hz] and
its setting without the speed (the panels).

Out:

* :func:`nip_orders` (``nip_orders.png``), the nip-force spectral map over speed: per nip and
  setting (e.g. per line load) a panel, the amplitude of the whole nip's force (summed over the
  segments) at each order over the first roll's speed, log scale; dashed, the orders of each
  roll of the nip at its own speed (a covered roll's runout orders), unless they are the first
  roll's (the same numbers);
* :func:`nip_spectrum` (``nip_spectrum.png``), the nip-force spectrum map over speed, read from
  each job's ``nips/<nip>/force`` [segments × time] itself: per nip and setting a panel, the
  first roll's speed across, the frequency up, the colour the Hann-windowed amplitude of the
  whole nip's force (summed over the segments, its mean removed) [N], log scale over
  ``MAP_DECADES`` decades; dotted, the first roll's orders 1–4 (k × speed). Forced lines lie on
  the orders, a barring or other self-excited vibration across them at its own frequency;
* :func:`nip_profile` (``nip_profile.png``), the cross-machine nip profile: per nip and setting
  a column, on top the static line load per segment [kN/m] over the axial position [mm] (every
  speed of the setting, one grey line each, and the drawn job's in colour), below each order's
  amplitude per segment [kN/m] at the job whose summed force has the largest line (its speed in
  the title).

Each is None when the document has no ``nips`` table (not a machine's run).
"""

from __future__ import annotations

import h5py
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from rotorsweep import PathLike

from ._common import MAP_DECADES, figure

#: Prefix and suffix of the order amplitude columns of the ``nips`` table.
AMP_PREFIX, AMP_SUFFIX = "amplitude_", "x_n"
#: Most panels (settings × nips) drawn; further ones are left out, the title says how many.
MAX_PANELS = 6
#: The first roll's orders drawn over the spectrum map.
MAP_ORDERS = (1, 2, 3, 4)


def has_nips(path: PathLike) -> bool:
    """Whether some job of the results file ``path`` holds a nip's records (``nips/<nip>``)."""
    with h5py.File(path, "r") as f:
        jobs = f.get("jobs")
        return jobs is not None and any("nips" in jobs[j] for j in jobs)


def nips_frame(doc: dict) -> pd.DataFrame | None:
    """The report's ``nips`` table as a DataFrame (one row per job, nip and segment), None
    without it."""
    table = next((t for t in doc.get("tables", [])
                  if isinstance(t, dict) and t.get("name") == "nips"), None)
    if table is None or not table.get("rows"):
        return None
    return pd.DataFrame(table["rows"], columns=table["columns"])


def _is_order(text: str) -> bool:
    """Whether ``text`` is an order (a number), as in ``amplitude_2x_n``."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def _orders(df: pd.DataFrame, side: str = "") -> list[tuple[str, str]]:
    """(column, order text) of every order amplitude column of the first roll (``side`` "") or
    of the nip's roll ``side`` ("a", "b"), in the table's order."""
    prefix = AMP_PREFIX + (f"{side}_" if side else "")
    return [(c, c[len(prefix):-len(AMP_SUFFIX)]) for c in df.columns
            if c.startswith(prefix) and c.endswith(AMP_SUFFIX)
            and _is_order(c[len(prefix):-len(AMP_SUFFIX)])]


def _roll_orders(df: pd.DataFrame, g: pd.DataFrame) -> list[tuple[str, str, str]]:
    """(column, order text, roll name) of the orders of each roll of the nip in the rows ``g``
    that are not the first roll's (tables without the rolls' columns: none)."""
    first = g[[c for c, _ in _orders(df)]].astype(float).to_numpy()
    out = []
    for side in ("a", "b"):
        cols = _orders(df, side)
        name_col = f"roll_{side}"
        if not cols or name_col not in g or len(cols) != first.shape[1]:
            continue
        mine = g[[c for c, _ in cols]].astype(float).to_numpy()
        if np.array_equal(mine, first, equal_nan=True) or not np.isfinite(mine).any():
            continue
        name = str(g[name_col].iloc[0])
        out.extend((c, text, name) for c, text in cols)
    return out


def _groups(df: pd.DataFrame, settings: pd.Series) -> list[tuple[str, pd.DataFrame]]:
    """(panel title, rows) per nip and setting, in the table's order."""
    df = df.assign(_setting=df["job_id"].map(settings).fillna(""))
    out = []
    for (nip, setting), rows in df.groupby(["nip", "_setting"], sort=False):
        title = f"nip {nip}" + (f", {setting}" if setting else "")
        out.append((title, rows))
    return out


def nip_orders(doc: dict, speeds: pd.Series, settings: pd.Series, study: str) -> Figure | None:
    """The nip-force spectral map (module doc): ``speeds`` the first roll's speed [Hz] per job
    (index job_id), ``settings`` each job's setting without the speed (index job_id). None
    without a ``nips`` table or with fewer than two speeds in every panel."""
    df = nips_frame(doc)
    if df is None:
        return None
    total = df[df["segment"] == "total"].assign(speed=lambda d: d["job_id"].map(speeds))
    groups = [(t, g.sort_values("speed")) for t, g in _groups(total, settings)
              if g["speed"].nunique() >= 2]
    if not groups:
        return None
    shown = groups[:MAX_PANELS]
    orders = _orders(df)
    fig = figure(figsize=(4.2 * len(shown) + 1.0, 4.2))
    axes = fig.subplots(1, len(shown), sharey=True, squeeze=False)[0]
    colours = [f"C{i}" for i in range(len(orders))]
    for ax, (title, g) in zip(axes, shown):
        for (col, text), colour in zip(orders, colours):
            y = g[col].astype(float).to_numpy()
            ok = np.isfinite(y) & (y > 0)
            if ok.any():
                ax.semilogy(g["speed"].to_numpy()[ok], y[ok], "o-", ms=3, color=colour,
                            label=f"{text}×")
        for i, (col, text, roll) in enumerate(_roll_orders(df, g)):
            y = g[col].astype(float).to_numpy()
            ok = np.isfinite(y) & (y > 0)
            if ok.any():
                ax.semilogy(g["speed"].to_numpy()[ok], y[ok], "s--", ms=3, color=f"C{i % 10}",
                            alpha=0.7, label=f"{text}× of {roll}")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("first roll's speed [Hz]")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("amplitude of the nip force [N]")
    axes[-1].legend(title="order", fontsize=8, loc="center left", bbox_to_anchor=(1.02, 0.5))
    more = f" ({len(groups) - len(shown)} more panels not shown)" if len(groups) > len(shown) else ""
    fig.suptitle(f"{study}: nip force (summed over the segments) at the first roll's orders "
                 f"(dashed: a roll's own orders){more}", fontsize=11)
    return fig


def nip_profile(doc: dict, speeds: pd.Series, settings: pd.Series, study: str) -> Figure | None:
    """The cross-machine nip profile (module doc); arguments as :func:`nip_orders`. None without
    a ``nips`` table."""
    df = nips_frame(doc)
    if df is None:
        return None
    orders = _orders(df)
    total = df[df["segment"] == "total"]
    segs = df[df["segment"] != "total"].copy()
    segs["z_mm"] = segs["z_mm"].astype(float)
    groups = _groups(total, settings)
    shown = groups[:MAX_PANELS]
    fig = figure(figsize=(4.2 * len(shown) + 1.0, 7.0))
    axes = fig.subplots(2, len(shown), sharex=True, squeeze=False)
    for c, (title, g) in enumerate(shown):
        # The job whose summed force has the largest line at any order.
        peak = g[[col for col, _ in orders]].astype(float).max(axis=1)
        job = g.loc[peak.idxmax(), "job_id"] if peak.notna().any() else g["job_id"].iloc[0]
        nip = g["nip"].iloc[0]
        top, bottom = axes[0][c], axes[1][c]
        for other in g["job_id"]:
            rows = segs[(segs["job_id"] == other) & (segs["nip"] == nip)].sort_values("z_mm")
            top.plot(rows["z_mm"], rows["line_load_kn_per_m"].astype(float), color="0.8", lw=0.8)
        rows = segs[(segs["job_id"] == job) & (segs["nip"] == nip)].sort_values("z_mm")
        length_m = rows["length_mm"].astype(float).to_numpy() / 1e3
        top.plot(rows["z_mm"], rows["line_load_kn_per_m"].astype(float), "o-", ms=3, color="C0",
                 label="static (drawn job)")
        top.plot([], [], color="0.8", label="static, other speeds")
        for i, (col, text) in enumerate(orders):
            y = rows[col].astype(float).to_numpy() / length_m / 1e3
            # An open segment carries nothing: a gap in the log-scale line.
            y = np.where(y > 0, y, np.nan)
            if np.isfinite(y).any() and np.nanmax(y) > 0:
                bottom.semilogy(rows["z_mm"], y, "o-", ms=3, color=f"C{i}", label=f"{text}×")
        speed = speeds.get(job, np.nan)
        top.set_title(f"{title}\nspeed {speed:g} Hz" if np.isfinite(speed) else title,
                      fontsize=10)
        top.grid(True, alpha=0.3)
        bottom.grid(True, which="both", alpha=0.3)
        bottom.set_xlabel("axial position z [mm]")
    axes[0][0].set_ylabel("static line load [kN/m]")
    axes[1][0].set_ylabel("dynamic amplitude [kN/m]")
    axes[0][-1].legend(fontsize=8, loc="center left", bbox_to_anchor=(1.02, 0.5))
    axes[1][-1].legend(title="order", fontsize=8, loc="center left", bbox_to_anchor=(1.02, 0.5))
    more = f" ({len(groups) - len(shown)} more not shown)" if len(groups) > len(shown) else ""
    fig.suptitle(f"{study}: cross-machine nip profile; the amplitudes at the speed of the largest "
                 f"line{more}", fontsize=11)
    return fig


def _nip_spectra(path: PathLike, jobs: list[str]) -> dict[str, dict[str, tuple]]:
    """Per nip and job, (frequencies [Hz], amplitudes [N]) of the nip's summed force: mean
    removed, Hann window, amplitudes scaled so that a sine of amplitude A reads A."""
    from rotorsweep import nip_forces

    out: dict[str, dict[str, tuple]] = {}
    with h5py.File(path, "r") as f:
        names = {j: list(f["jobs"][j]["nips"]) for j in jobs
                 if j in f["jobs"] and "nips" in f["jobs"][j]}
    for job, nips in names.items():
        for nip in nips:
            da = nip_forces(path, job, nip=nip)
            t = da["time"].to_numpy()
            if len(t) < 8:
                continue
            x = da.sum("z_mm").to_numpy()
            x = x - x.mean()
            w = np.hanning(len(x))
            amp = 2.0 * np.abs(np.fft.rfft(x * w)) / w.sum()
            freq = np.fft.rfftfreq(len(x), d=float(np.median(np.diff(t))))
            out.setdefault(nip, {})[job] = (freq, amp)
    return out


def nip_spectrum(path: PathLike, speeds: pd.Series, settings: pd.Series,
                 study: str) -> Figure | None:
    """The nip-force spectrum map over speed (module doc) of the results file ``path``;
    ``speeds`` and ``settings`` as :func:`nip_orders`. None without nips or with fewer than two
    speeds in every panel."""
    jobs = [str(j) for j in speeds.index if np.isfinite(speeds[j])]
    spectra = _nip_spectra(path, jobs)
    panels = []
    for nip, per_job in spectra.items():
        by_setting: dict[str, list[str]] = {}
        for job in per_job:
            by_setting.setdefault(str(settings.get(job, "")), []).append(job)
        for setting, group in by_setting.items():
            group = sorted(group, key=lambda j: float(speeds[j]))
            if len({float(speeds[j]) for j in group}) >= 2:
                title = f"nip {nip}" + (f", {setting}" if setting else "")
                panels.append((title, [(float(speeds[j]), *per_job[j]) for j in group]))
    if not panels:
        return None
    shown = panels[:MAX_PANELS]
    fig = figure(figsize=(4.4 * len(shown) + 1.2, 4.6))
    axes = fig.subplots(1, len(shown), sharey=True, squeeze=False)[0]
    top = max(float(a.max()) for _, rows in shown for _, _, a in rows)
    low = top * 10.0 ** (-MAP_DECADES)
    from matplotlib.colors import LogNorm

    norm = LogNorm(vmin=low, vmax=top)
    mesh = None
    for ax, (title, rows) in zip(axes, shown):
        s = np.array([r[0] for r in rows])
        mid = 0.5 * (s[1:] + s[:-1])
        edges = np.concatenate([[s[0] - (mid[0] - s[0])], mid, [s[-1] + (s[-1] - mid[-1])]])
        for k, (_, freq, amp) in enumerate(rows):
            df = freq[1] - freq[0]
            fe = np.concatenate([freq - 0.5 * df, [freq[-1] + 0.5 * df]])
            mesh = ax.pcolormesh([edges[k], edges[k + 1]], fe, np.clip(amp, low, None)[:, None],
                                 norm=norm, cmap="magma", shading="flat")
        fmax = max(float(r[1][-1]) for r in rows)
        for n in MAP_ORDERS:
            ax.plot(edges, n * edges, ":", color="w", lw=0.8)
        ax.set_ylim(0.0, fmax)
        ax.set_xlim(edges[0], edges[-1])
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("first roll's speed [Hz]")
    axes[0].set_ylabel("frequency [Hz]")
    fig.colorbar(mesh, ax=list(axes), label="amplitude of the nip force [N]")
    more = f" ({len(panels) - len(shown)} more panels not shown)" if len(panels) > len(shown) else ""
    fig.suptitle(f"{study}: nip force spectrum (summed over the segments, Hann window; dotted: "
                 f"the first roll's orders {', '.join(f'{n}×' for n in MAP_ORDERS)}){more}", fontsize=11)
    return fig
