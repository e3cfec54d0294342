"""The figures of a calibration (``rotorsweep calibrate CAL.toml -o OUT.h5``): the target rows
measured and modelled, their normalised residuals, the cost over the evaluations, each
parameter's path and the fitted parameters' correlations.

In: the calibration results file, read with :func:`rotorsweep.calibration` (every number as the
calibration wrote it; docs/calibration.md lists the layout). Out: up to seven figures, each only
when the file holds its rows:

* ``calibration_rows.png``: every row that is not a record's (``[[targets]]``,
  ``[[resonances]]``, ``[[frequencies]]``), a panel per kind of output (``peak_speed_hz``,
  ``peak_amplitude_um``, ``critical_speed_hz``, …, in the output's unit), its rows along x
  grouped by order (``2x`` rows together, then ``3x``, …) and sensor: measured ± σ (black, error
  bar), the model at the start (grey square) and at the fit (blue diamond); a log scale where the
  panel's values are positive and span more than a decade;
* ``calibration_resonances.png``: each ``[[resonances]]`` table that gives both a speed and an
  amplitude as a point in the plane of resonance speed [Hz] and amplitude [µm]: measured with
  ± σ in both, the model at the start (square) and at the fit (diamond) joined by an arrow, a
  colour per table (its channel and order);
* ``calibration_records.png``: the rows of ``[[records]]`` (``order_re_um`` / ``order_im_um``,
  the real and imaginary part of a measured block's complex order amplitude [µm]) over the
  block's speed [Hz], a column per record channel, order and job, the real part above the
  imaginary: measured ± σ (dots, error bars), the model at the start (grey, dashed) and at the
  fit (blue);
* ``calibration_residuals.png``: the normalised residual of every row in the file's order,
  √w (model − measured)/σ, at the start (above, computed from the stored ``initial``,
  ``measured``, ``std`` and ``weight``; symmetric-log scale) and at the fit (below, the stored
  ``residual``; ±1 and ±2 dashed), coloured by the row's group (a resonance, frequency or target
  table's output kind, a record's channel);
* ``calibration_cost.png``: the cost ½ Σ r² [1] of every evaluation over its index (log scale;
  marker by role: start, finite difference, trial step) with the accepted path (the lowest cost
  of the start and the trial steps so far), and the accepted cost per iteration;
* ``calibration_parameters.png``: a panel per parameter, its value at every evaluation (marker
  by role) with the accepted path, its bounds (dashed) and the fitted value ± standard error
  (band); a log scale for a parameter fitted on one;
* ``calibration_correlation.png``: with two parameters or more, the fitted parameters'
  correlation matrix as a heat map (−1 blue … +1 red), each cell with its value to two decimals;
  a cell without a value (a held parameter's row and column) grey and marked "–"; none when no
  cell has a value (no standard errors: as many rows as free parameters).

Numbers in titles are written as the report writes them (:func:`~._common.significant`)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib import colormaps
from matplotlib.figure import Figure

import rotorsweep as rp
from rotorsweep import PathLike

from ._common import PlotError, figure, grid, significant

#: A record row's output: ``order_re_um:<sensor>/<dir>:<order>x@<speed>Hz``.
RECORD_OUTPUT = re.compile(r"^order_(re|im)_um:(?P<channel>[^:]+):(?P<order>[^:@]+)x"
                           r"@(?P<speed>[^@]+)Hz$")
#: A row output's order suffix (``…:2x``).
ORDER_SUFFIX = re.compile(r":(?P<order>[0-9.eE+-]+)x$")
#: The marker and colour of each evaluation role (the role before ``:``).
ROLES = {"start": ("o", "k", "start"), "jacobian": (".", "0.55", "finite difference"),
         "step": ("^", "C1", "trial step")}
#: Most rows whose outputs label the x axis of the residual figure (more: a row index).
MAX_NAMED_ROWS = 40
#: Record groups per row of panels in ``calibration_records.png``.
RECORD_COLUMNS = 3


def _unit(kind: str) -> str:
    """The unit an output kind's name states."""
    for suffix, unit in (("_hz", "Hz"), ("_um", "µm"), ("_n", "N")):
        if kind.endswith(suffix):
            return unit
    return "1"


def _order(output: str) -> float:
    """The order of a row's output (``…:2x`` → 2), +inf for none."""
    m = ORDER_SUFFIX.search(output)
    try:
        return float(m["order"]) if m else np.inf
    except ValueError:
        return np.inf


def _split(rows: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The rows of records (with ``part``, ``channel``, ``order``, ``speed_hz`` parsed from the
    output) and the other rows (with ``kind`` and ``label``)."""
    parsed = rows["output"].str.extract(RECORD_OUTPUT)
    is_record = parsed["channel"].notna()
    records = rows[is_record].copy()
    records["part"] = parsed.loc[is_record, 0]
    records["channel"] = parsed.loc[is_record, "channel"]
    records["order"] = parsed.loc[is_record, "order"]
    records["speed_hz"] = pd.to_numeric(parsed.loc[is_record, "speed"], errors="coerce")
    other = rows[~is_record].copy()
    kind, _, rest = other["output"].str.partition(":").T.to_numpy() if len(other) else ([], [], [])
    other["kind"] = list(kind)
    other["label"] = [r or k for k, r in zip(kind, rest)]
    if other["job"].nunique() > 1:
        other["label"] = other["label"] + " (job " + other["job"].astype(str) + ")"
    return records, other


def _group(rows: pd.DataFrame) -> pd.Series:
    """Each row's group in the residual figure: a record's channel and order, or the output
    kind."""
    records, other = _split(rows)
    g = pd.Series("", index=rows.index)
    g[records.index] = "record " + records["channel"] + " " + records["order"] + "x"
    g[other.index] = other["kind"]
    return g


def _log_fit(values: np.ndarray) -> bool:
    """Whether a panel of these values reads better on a log scale: all positive, over more
    than a decade."""
    v = values[np.isfinite(values)]
    return len(v) > 1 and bool((v > 0).all()) and v.max() > 10 * v.min()


def target_rows(rows: pd.DataFrame, title: str) -> Figure | None:
    """``calibration_rows.png`` (module doc); None without rows other than records'."""
    _, other = _split(rows)
    if other.empty:
        return None
    kinds = list(dict.fromkeys(other["kind"]))
    width = max(len(other[other["kind"] == k]) for k in kinds)
    fig = figure(figsize=(min(max(7.5, 3.2 + 0.55 * width), 15.0), 2.9 * len(kinds) + 1.4))
    axes = fig.subplots(len(kinds), 1, squeeze=False)[:, 0]
    for ax, kind in zip(axes, kinds):
        g = other[other["kind"] == kind].copy()
        g["_order"] = g["output"].map(_order)
        g = g.sort_values(["_order", "label"], kind="stable")
        x = np.arange(len(g))
        ax.errorbar(x - 0.15, g["measured"], yerr=g["std"], fmt="o", color="k", ms=5,
                    capsize=3, label="measured ± σ")
        ax.plot(x, g["initial"], "s", mfc="none", mec="0.45", ms=6, label="model at start")
        ax.plot(x + 0.15, g["model"], "D", color="C0", ms=5, label="model at fit")
        values = np.concatenate([g[c].to_numpy(float) for c in ("measured", "initial", "model")])
        if _log_fit(values):
            ax.set_yscale("log")
        ax.set_xticks(x, list(g["label"]), rotation=30 if len(g) > 4 else 0,
                      ha="right" if len(g) > 4 else "center", fontsize="small")
        ax.set_xlim(-0.6, len(g) - 0.4)
        ax.set_ylabel(f"{kind} [{_unit(kind)}]")
        ax.grid(alpha=0.3, which="both")
    fig.legend(*axes[0].get_legend_handles_labels(), fontsize="small", ncols=3,
               loc="outside lower center")
    fig.suptitle(f"{title}: target rows, measured and modelled")
    return fig


def record_rows(rows: pd.DataFrame, title: str) -> Figure | None:
    """``calibration_records.png`` (module doc); None without record rows."""
    records, _ = _split(rows)
    if records.empty:
        return None
    records["group"] = records["channel"] + " " + records["order"] + "x"
    if records["job"].nunique() > 1:
        records["group"] += " (job " + records["job"].astype(str) + ")"
    groups = list(dict.fromkeys(records["group"]))
    bands, cols = grid(len(groups), RECORD_COLUMNS)
    fig = figure(figsize=(4.6 * cols + 0.8, 5.6 * bands + 0.6))
    axes = fig.subplots(2 * bands, cols, squeeze=False, sharex="col")
    for n, group in enumerate(groups):
        band, col = divmod(n, cols)
        for i, (part, name) in enumerate((("re", "real part"), ("im", "imaginary part"))):
            ax = axes[2 * band + i, col]
            g = records[(records["group"] == group) & (records["part"] == part)]
            g = g.sort_values("speed_hz", kind="stable")
            ax.errorbar(g["speed_hz"], g["measured"], yerr=g["std"], fmt=".", color="k",
                        ms=3, elinewidth=0.6, label="measured ± σ")
            ax.plot(g["speed_hz"], g["initial"], "--", color="0.5", lw=1, label="model at start")
            ax.plot(g["speed_hz"], g["model"], "-", color="C0", lw=1.2, label="model at fit")
            ax.set_title(f"{group}: {name}", fontsize="medium")
            ax.set_ylabel("order amplitude [µm]")
            ax.grid(alpha=0.3)
            if i == 1:
                ax.set_xlabel("speed, block mean [Hz]")
    for n in range(len(groups), bands * cols):
        band, col = divmod(n, cols)
        axes[2 * band, col].set_visible(False)
        axes[2 * band + 1, col].set_visible(False)
    fig.legend(*axes[0, 0].get_legend_handles_labels(), fontsize="small", ncols=3,
               loc="outside lower center")
    fig.suptitle(f"{title}: records, complex order amplitude A e^iφ")
    return fig


#: A resonance row's target key: ``resonances[<k>].speed_hz`` or ``….amplitude_um``.
RESONANCE_TARGET = re.compile(r"^(?P<table>resonances\[\d+\])\.(?P<what>speed_hz|amplitude_um)$")


def resonance_pairs(rows: pd.DataFrame) -> pd.DataFrame:
    """The ``[[resonances]]`` tables that give both a speed and an amplitude row: one row each
    with the table, its channel and order (``centre/vertical:2x``), and per quantity (``speed``,
    ``amplitude``) its ``measured``, ``std``, ``initial`` and ``model``."""
    m = rows["target"].str.extract(RESONANCE_TARGET)
    on = m["table"].notna()
    if not on.any():
        return pd.DataFrame()
    r = rows[on].assign(table=m.loc[on, "table"], what=m.loc[on, "what"])
    wide = r.pivot(index="table", columns="what",
                   values=["measured", "std", "initial", "model", "output"])
    if ("measured", "speed_hz") not in wide or ("measured", "amplitude_um") not in wide:
        return pd.DataFrame()
    wide = wide.dropna(subset=[("measured", "speed_hz"), ("measured", "amplitude_um")])
    out = pd.DataFrame(index=wide.index)
    out["label"] = wide[("output", "amplitude_um")].str.partition(":")[2]
    for q, what in (("speed", "speed_hz"), ("amplitude", "amplitude_um")):
        for c in ("measured", "std", "initial", "model"):
            out[f"{q}_{c}"] = wide[(c, what)].astype(float)
    # The file's order of the tables.
    return out.loc[[t for t in dict.fromkeys(r["table"]) if t in out.index]]


def resonances(rows: pd.DataFrame, title: str) -> Figure | None:
    """``calibration_resonances.png`` (module doc); None without a resonance table that gives
    both a speed and an amplitude."""
    pairs = resonance_pairs(rows)
    if pairs.empty:
        return None
    fig = figure(figsize=(8.0, 5.6))
    ax = fig.subplots()
    for i, (_, p) in enumerate(pairs.iterrows()):
        colour = f"C{i % 10}"
        ax.errorbar(p["speed_measured"], p["amplitude_measured"], xerr=p["speed_std"],
                    yerr=p["amplitude_std"], fmt="o", color=colour, ms=6, capsize=3,
                    label=p["label"])
        ax.plot(p["speed_initial"], p["amplitude_initial"], "s", mfc="none", mec=colour, ms=7)
        ax.plot(p["speed_model"], p["amplitude_model"], "D", color=colour, ms=6)
        ax.annotate("", xy=(p["speed_model"], p["amplitude_model"]),
                    xytext=(p["speed_initial"], p["amplitude_initial"]),
                    arrowprops=dict(arrowstyle="->", color=colour, lw=0.8, alpha=0.7))
    values = pairs[["amplitude_measured", "amplitude_initial", "amplitude_model"]].to_numpy(float)
    if _log_fit(values.ravel()):
        ax.set_yscale("log")
    ax.set_xlabel("resonance speed [Hz]")
    ax.set_ylabel("resonance amplitude [µm]")
    ax.grid(alpha=0.3, which="both")
    handles, labels = ax.get_legend_handles_labels()
    handles += [ax.plot([], [], "s", mfc="none", mec="k")[0], ax.plot([], [], "D", color="k")[0]]
    labels += ["model at start", "model at fit"]
    fig.legend(handles, labels, fontsize="small", ncols=min(len(labels), 4),
               loc="outside lower center")
    fig.suptitle(f"{title}: resonances, measured ± σ, model from the start (□) to the fit (◆)")
    return fig


def residuals(rows: pd.DataFrame, title: str) -> Figure | None:
    """``calibration_residuals.png`` (module doc); None without rows."""
    if rows.empty:
        return None
    start = (np.sqrt(rows["weight"]) * (rows["initial"] - rows["measured"]) / rows["std"])
    groups = _group(rows)
    names = list(dict.fromkeys(groups))
    colour = {g: f"C{i % 10}" for i, g in enumerate(names)}
    fig = figure(figsize=(min(max(8.0, 4.0 + 0.25 * len(rows)), 14.0),
                          7.4 if len(rows) <= MAX_NAMED_ROWS else 6.4))
    axes = fig.subplots(2, 1, sharex=True)
    x = np.arange(len(rows))
    for ax, r, when in ((axes[0], start.to_numpy(float), "at the start"),
                        (axes[1], rows["residual"].to_numpy(float), "at the fit")):
        for g in names:
            on = (groups == g).to_numpy()
            ax.vlines(x[on], 0, r[on], color=colour[g], lw=1.5 if len(rows) <= 60 else 0.8)
            ax.plot(x[on], r[on], "o", color=colour[g], ms=3 if len(rows) > 60 else 4, label=g)
        ax.axhline(0, color="k", lw=0.6)
        ax.set_ylabel(f"residual {when} [σ]")
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_yscale("symlog", linthresh=1.0)
    # Room beyond the largest residual (symmetric-log: by a factor), and beside the first and
    # last row.
    top = np.nanmax(np.abs(start.to_numpy(float)), initial=1.0)
    axes[0].set_ylim(-2.0 * top, 2.0 * top)
    axes[1].set_xlim(-0.02 * len(rows) - 0.6, 1.02 * len(rows) - 0.4)
    for s in (-2, -1, 1, 2):
        axes[1].axhline(s, color="0.5", ls="--", lw=0.7)
    if len(rows) <= MAX_NAMED_ROWS:
        axes[1].set_xticks(x, list(rows["output"]), rotation=60, ha="right", fontsize="x-small")
    else:
        axes[1].set_xlabel("row, in the file's order")
    fig.legend(*axes[0].get_legend_handles_labels(), fontsize="small",
               ncols=min(len(names), 4), loc="outside lower center")
    fig.suptitle(f"{title}: normalised residuals √w (model − measured)/σ per row")
    return fig


def _accepted(ev: pd.DataFrame) -> pd.Series:
    """The accepted path: at each evaluation, the index of the lowest-cost start or trial step
    evaluated so far (the point the fit stands at)."""
    base = ev["role"].str.partition(":")[0]
    best, at, out = np.inf, -1, []
    for i, (role, cost) in enumerate(zip(base, ev["cost"])):
        if role in ("start", "step") and cost < best:
            best, at = cost, i
        out.append(at)
    return pd.Series(out, index=ev.index)


def _history(ax, ev: pd.DataFrame, y: pd.Series, path: pd.Series, label: str) -> None:
    """The evaluations' values ``y`` over their index, marker and colour by role, and along the
    accepted ``path`` (:func:`_accepted`) as a step line labelled ``label``."""
    base = ev["role"].str.partition(":")[0]
    for role, (marker, colour, name) in ROLES.items():
        on = base == role
        if on.any():
            ax.plot(ev.loc[on, "index"], y[on], marker, color=colour, ms=5, ls="none",
                    label=name, zorder=3)
    ok = path >= 0
    ax.step(ev.loc[ok, "index"], y.to_numpy()[path[ok]], where="post", color="C0", lw=1.2,
            label=label)


def cost(ev: pd.DataFrame, attrs: dict, title: str) -> Figure | None:
    """``calibration_cost.png`` (module doc); None without evaluations."""
    if ev.empty:
        return None
    fig = figure(figsize=(11.5, 4.6))
    left, right = fig.subplots(1, 2, width_ratios=(3, 2))
    _history(left, ev, ev["cost"], _accepted(ev), "accepted (lowest so far)")
    left.set_yscale("log")
    left.set_xlabel("evaluation")
    left.set_ylabel("cost ½ Σ r² [1]")
    left.grid(alpha=0.3, which="both")
    left.legend(fontsize="small")
    base = ev["role"].str.partition(":")[0]
    tried = ev[base.isin(["start", "step"])]
    per_iteration = tried.groupby("iteration")["cost"].min().cummin()
    right.plot(per_iteration.index, per_iteration.to_numpy(), "o-", color="C0")
    right.set_yscale("log")
    right.set_xlabel("iteration (accepted steps)")
    right.set_ylabel("cost after the iteration [1]")
    right.grid(alpha=0.3, which="both")
    if len(per_iteration) > 0:
        right.set_xticks(per_iteration.index)
    right.set_title(f"stop: {attrs.get('stop', '')}", fontsize="medium")
    fig.suptitle(f"{title}: cost {significant(attrs['start_cost'], 4)} → "
                 f"{significant(attrs['cost'], 4)}, reduced χ² "
                 f"{significant(attrs['reduced_chi_square'], 3)} "
                 f"({int(attrs['evaluation_count'])} evaluations)")
    return fig


def parameters(params: pd.DataFrame, ev: pd.DataFrame, title: str) -> Figure | None:
    """``calibration_parameters.png`` (module doc); None without evaluations."""
    if ev.empty or params.empty:
        return None
    n = len(params)
    bands, cols = grid(n)
    fig = figure(figsize=(4.8 * cols + 0.6, 3.9 * bands + 0.8))
    axes = fig.subplots(bands, cols, squeeze=False).ravel()
    path = _accepted(ev)
    for ax, (_, p) in zip(axes, params.iterrows()):
        y = ev[f"value:{p['name']}"]
        _history(ax, ev, y, path, "accepted")
        value, err = float(p["value"]), float(p["std_error"])
        if np.isfinite(err) and err > 0:
            ax.axhspan(value - err, value + err, color="C2", alpha=0.25, lw=0,
                       label="fit ± std error")
        ax.axhline(value, color="C2", lw=1)
        log = p["scale"] == "log"
        if log:
            ax.set_yscale("log")
        # The view spans the evaluated values and the fit's band; a bound shows where it lies
        # within (or near) them.
        seen = np.concatenate([y.to_numpy(float), [value - err, value + err]
                               if np.isfinite(err) else [value]])
        seen = seen[np.isfinite(seen) & ((seen > 0) | (not log))]
        lo, hi = float(seen.min()), float(seen.max())
        if log:
            pad = (hi / lo) ** 0.08 if hi > lo else 1.05
            lo, hi = lo / pad, hi * pad
        else:
            pad = 0.08 * (hi - lo) if hi > lo else 0.05 * max(abs(hi), 1e-300)
            lo, hi = lo - pad, hi + pad
        for bound in (p["lower"], p["upper"]):
            ax.axhline(bound, color="0.4", ls="--", lw=0.8)
        ax.plot([], [], color="0.4", ls="--", lw=0.8, label="bound")
        ax.set_ylim(lo, hi)
        ax.set_title(f"{p['name']}: {significant(value, 4)} ± {significant(err, 2)}"
                     f"{' (at a bound)' if p['at_bound'] else ''}\n"
                     f"start {significant(p['initial'], 4)}, bounds "
                     f"{significant(p['lower'], 4)} … {significant(p['upper'], 4)}",
                     fontsize="medium")
        ax.set_xlabel("evaluation")
        ax.set_ylabel("value [the keys' unit]")
        ax.grid(alpha=0.3, which="both")
    for ax in axes[n:]:
        ax.set_visible(False)
    fig.legend(*axes[0].get_legend_handles_labels(), fontsize="small", ncols=3 * cols,
               loc="outside lower center")
    fig.suptitle(f"{title}: parameter values over the evaluations")
    return fig


#: Correlations whose cells get white text (the colour map is dark beyond them).
DARK_CELL = 0.6


def correlation(corr: pd.DataFrame, title: str) -> Figure | None:
    """``calibration_correlation.png`` (module doc) of the correlation matrix ``corr`` (indexed
    by parameter name both ways, NaN without a value); None below two parameters or without a
    value."""
    n = len(corr)
    values = corr.to_numpy(float)
    if n < 2 or not np.isfinite(values).any():
        return None
    cmap = colormaps["RdBu_r"].with_extremes(bad="0.85")
    side = min(max(4.2, 1.0 + 0.75 * n), 12.0)
    fig = figure(figsize=(side + 1.3, side))
    ax = fig.subplots()
    image = ax.imshow(np.ma.masked_invalid(values), cmap=cmap, vmin=-1.0, vmax=1.0)
    size = "medium" if n <= 6 else "small" if n <= 10 else "x-small"
    for i in range(n):
        for j in range(n):
            v = values[i, j]
            text = f"{v:.2f}".replace("-", "−") if np.isfinite(v) else "–"
            dark = np.isfinite(v) and abs(v) > DARK_CELL
            ax.text(j, i, text, ha="center", va="center", fontsize=size,
                    color="white" if dark else "black")
    names = [str(c) for c in corr.columns]
    ax.set_xticks(range(n), names, rotation=30 if n > 3 else 0,
                  ha="right" if n > 3 else "center")
    ax.set_yticks(range(n), [str(i) for i in corr.index])
    ax.set_xticks(np.arange(n + 1) - 0.5, minor=True)
    ax.set_yticks(np.arange(n + 1) - 0.5, minor=True)
    ax.grid(which="minor", color="white", lw=1.5)
    ax.tick_params(which="minor", length=0)
    fig.colorbar(image, ax=ax, label="correlation [1]", shrink=0.85)
    fig.suptitle(f"{title}: correlation of the fitted parameters")
    return fig


def calibration_figures(path: PathLike) -> list[tuple[str, Figure | None]]:
    """The figures of the calibration file ``path``, named, in the module doc's order (None
    where the file has nothing for one)."""
    try:
        c = rp.calibration(path)
    except rp.RotorsweepError as e:
        raise PlotError(str(e)) from None
    title = str(c["attrs"].get("name", Path(path).stem))
    rows, ev, params = c["rows"], c["evaluations"], c["parameters"]
    return [
        ("calibration_rows.png", target_rows(rows, title)),
        ("calibration_resonances.png", resonances(rows, title)),
        ("calibration_records.png", record_rows(rows, title)),
        ("calibration_residuals.png", residuals(rows, title)),
        ("calibration_cost.png", cost(ev, c["attrs"], title)),
        ("calibration_parameters.png", parameters(params, ev, title)),
        ("calibration_correlation.png", correlation(c["correlation"], title)),
    ]
