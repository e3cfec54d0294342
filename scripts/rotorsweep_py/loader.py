"""Read rotorsweep's HDF5 results into numpy arrays, dicts and pandas DataFrames.

A results file (``rotorsweep run STUDY -o OUT.h5``; ``rotorsweep merge`` joins shard files) holds

* file attributes: tool, tool_version, created_utc, host, threads, command, study_name,
  study_path, study_text, varying_keys (newline-separated dotted keys), shard;
* ``/jobs/<job_id>`` and ``/references/<reference_id>``: scalar attributes (status, cause,
  solver statistics, errors against the reference, every override under its dotted key) and
  1-D datasets (``time`` [s], ``runout/<sensor>/{vertical,horizontal}`` [um], optionally
  ``journal/…``, ``stand/…``, ``contact/…``, ``modal/…``), each with a ``units`` attribute;
* ``/models/<model_id>``: the reduced models' modes (``freq_hz``, ``index``, ``labels``,
  ``kinds``, optional ``strain_energy_share``);
* ``/summary``: one row per job (compound table);
* ``/analysis`` (post-processing by ``run`` and ``merge``): compound tables ``lines``,
  ``resonances`` and, with an ``[analysis] baseline``, ``trial_mass``; ``sweeps/<n>``, one per
  set of jobs that differ only in ``speed.hz``, with the line amplitudes at the study's orders and
  the spectral maps (speed × frequency).

``rotorsweep simulate SCENE -o RUN.h5`` writes ``/jobs/<scene name>`` only; every reader here
that does not need ``/summary`` or ``/models`` works on it too, and :func:`load_summary` builds
its rows from the job attributes.

Every function takes a path and opens the file read-only for the duration of the call.
"""

from __future__ import annotations

import os
from typing import Any, TypedDict, Union

import h5py
import numpy as np
import pandas as pd

PathLike = Union[str, "os.PathLike[str]"]

#: Groups that hold runs: study jobs, then the reference runs they are compared with.
RUN_GROUPS = ("jobs", "references")

#: Summary columns that count things; stored as uint64 (float64 in files before 0.2), returned as
#: pandas' nullable Int64.
COUNT_COLUMNS = (
    "job_index",
    "steps",
    "rejected_steps",
    "newton_iterations",
    "jacobian_evals",
    "rhs_evals",
)


class Job(TypedDict):
    """One run as :func:`load_job` returns it."""

    id: str
    #: "jobs" or "references".
    group: str
    #: Scalar attributes as Python values (str, int, float; NaN where the file has NaN).
    attrs: dict[str, Any]
    #: Datasets by path relative to the run's group, e.g. "time", "runout/centre/vertical".
    data: dict[str, np.ndarray]
    #: The ``units`` attribute of each dataset ("" where a dataset has none).
    units: dict[str, str]


class Sweep(TypedDict):
    """One speed sweep (``/analysis/sweeps/<n>``) as :func:`sweeps` returns it."""

    n: int
    #: The other varying keys' values, "key=value; …" (labels where the axis has labels).
    fixed: str
    #: [S] spin speeds [Hz], ascending.
    speed_hz: np.ndarray
    #: [S] the job at each speed.
    job_ids: list[str]
    #: [K] orders of the lines (multiples of the speed).
    orders: np.ndarray
    #: Channel ("centre/vertical", …) → [S × K] line amplitudes [um].
    lines: dict[str, np.ndarray]
    #: [F] frequencies of the maps [Hz]; None when the sweep has no maps.
    freq_hz: np.ndarray | None
    #: Channel → [S × F] spectral map [um] (amplitude-correct Hanning spectra); {} without maps.
    maps: dict[str, np.ndarray]


class Model(TypedDict):
    """One reduced model as :func:`models` returns it."""

    #: Scalar attributes (modes, elements, mass_kg).
    attrs: dict[str, Any]
    #: One row per modal coordinate: index, freq_hz, label, kind[, strain_energy_share].
    #: ``modes.attrs["units"]`` maps columns to units.
    modes: pd.DataFrame


def _value(v: Any) -> Any:
    """An attribute value as a plain Python value (str, int, float) where it is a scalar."""
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, np.ndarray) and v.shape == ():
        v = v[()]
    if isinstance(v, np.generic):
        return _value(v.item())
    return v


def _attrs(obj: h5py.HLObject) -> dict[str, Any]:
    return {k: _value(v) for k, v in obj.attrs.items()}


def _read(ds: h5py.Dataset) -> np.ndarray:
    """A dataset as a numpy array; variable-length strings as an object array of str."""
    if h5py.check_string_dtype(ds.dtype) is not None:
        return np.asarray(ds.asstr()[()], dtype=object)
    return np.asarray(ds[()])


def _table(ds: h5py.Dataset) -> pd.DataFrame:
    """A compound dataset as a DataFrame, its text columns as ``str``.

    rotorsweep writes text as variable-length UTF-8, which h5py returns inside a compound
    dataset as ``bytes`` (object columns); the one-line decode is
    ``df[c] = df[c].str.decode("utf-8")``. Older files' fixed-length ASCII columns ("S") are
    decoded the same way. The units of each column are in ``df.attrs["units"]`` (from the
    dataset's ``units:<column>`` attributes).
    """
    table = ds[()]
    df = pd.DataFrame(table)
    for name in table.dtype.names or ():
        kind = table.dtype[name].kind
        if kind == "S" or (kind == "O" and h5py.check_string_dtype(ds.dtype[name]) is not None):
            df[name] = [b.decode("utf-8", "replace") if isinstance(b, bytes) else b for b in table[name]]
    df.attrs["units"] = {
        name: str(_value(ds.attrs[f"units:{name}"]))
        for name in table.dtype.names or ()
        if f"units:{name}" in ds.attrs
    }
    return df


def _channel_arrays(g: h5py.Group) -> dict[str, np.ndarray]:
    """The datasets ``<sensor>/<dir>`` under ``g`` by channel name ("centre/vertical", …)."""
    out: dict[str, np.ndarray] = {}

    def visit(name: str, obj: h5py.HLObject) -> None:
        if isinstance(obj, h5py.Dataset):
            out[name] = _read(obj)

    g.visititems(visit)
    return out


def _run_group(f: h5py.File, run_id: str) -> h5py.Group:
    for name in RUN_GROUPS:
        if name in f and run_id in f[name]:
            return f[name][run_id]
    known = [i for name in RUN_GROUPS if name in f for i in f[name]]
    shown = ", ".join(known[:8]) + (", …" if len(known) > 8 else "")
    raise KeyError(f"{f.filename}: no job or reference {run_id!r} (there are: {shown})")


def file_attrs(path: PathLike) -> dict[str, Any]:
    """The file's provenance attributes (tool, tool_version, command, study_text, …)."""
    with h5py.File(path, "r") as f:
        return _attrs(f)


def varying_keys(path: PathLike) -> list[str]:
    """The study's varying dotted keys, in axis order ([] for a ``simulate`` file)."""
    text = file_attrs(path).get("varying_keys", "")
    return [k for k in str(text).split("\n") if k]


def job_ids(path: PathLike, group: str = "jobs") -> list[str]:
    """Ids of the runs in ``/jobs`` (or ``group="references"``), in job-index order."""
    with h5py.File(path, "r") as f:
        if group not in f:
            return []
        g = f[group]
        index = {i: float(_value(g[i].attrs.get("job_index", np.nan))) for i in g}
    # Job-index order (as the summary), runs without an index (references, simulate) by name.
    return sorted(index, key=lambda i: (np.isnan(index[i]), np.nan_to_num(index[i]), i))


def load_summary(path: PathLike, *, index: bool = False) -> pd.DataFrame:
    """The ``/summary`` table: one row per job, in job-index order.

    Text columns (job_id, status, cause, error_cause, integrator, modes, label, text parameters)
    are decoded from the file's UTF-8 bytes to ``str``; the counts in :data:`COUNT_COLUMNS` become
    nullable integers. Varying parameters keep their dotted names (``df["speed.hz"]``; in
    ``DataFrame.query`` write them in backticks); a varying ``solver.integrator``, which the file
    keeps only as the ``integrator`` column, is also given its dotted key. With ``index=True`` job_id is the index,
    otherwise a column. A file without ``/summary`` (``rotorsweep simulate``) gets one row per
    run built from the runs' scalar attributes.
    """
    with h5py.File(path, "r") as f:
        if "summary" in f:
            df = _table(f["summary"])
            # A varying solver.integrator is stored only as the "integrator" column; give it its
            # dotted key too, so that df[varying_keys(path)] works.
            varying = str(_value(f.attrs.get("varying_keys", ""))).split("\n")
            if "solver.integrator" in varying and "solver.integrator" not in df and "integrator" in df:
                df["solver.integrator"] = df["integrator"]
        else:
            rows = []
            for run_id in f.get("jobs", {}):
                g = f["jobs"][run_id]
                rows.append({"job_id": run_id, **_attrs(g)})
            df = pd.DataFrame(rows)
    for name in COUNT_COLUMNS:
        if name in df:
            col = pd.to_numeric(df[name], errors="coerce")
            if bool((col.dropna() % 1 == 0).all()):
                df[name] = col.astype("Int64")
    return df.set_index("job_id") if index and "job_id" in df else df


def load_job(path: PathLike, job_id: str) -> Job:
    """One run (from ``/jobs``, else ``/references``): attributes, datasets and their units."""
    with h5py.File(path, "r") as f:
        g = _run_group(f, job_id)
        data: dict[str, np.ndarray] = {}
        units: dict[str, str] = {}

        def visit(name: str, obj: h5py.HLObject) -> None:
            if isinstance(obj, h5py.Dataset):
                data[name] = _read(obj)
                units[name] = str(_value(obj.attrs.get("units", "")))

        g.visititems(visit)
        return Job(
            id=job_id, group=g.parent.name.strip("/"), attrs=_attrs(g), data=data, units=units
        )


def channels(path: PathLike, job_id: str) -> list[str]:
    """Names of a run's sampled channels (every dataset but ``time``), e.g. "runout/drive/vertical"."""
    names: list[str] = []
    with h5py.File(path, "r") as f:
        g = _run_group(f, job_id)
        g.visititems(
            lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) and n != "time" else None
        )
    return names


def channel(path: PathLike, job_id: str, name: str) -> tuple[np.ndarray, np.ndarray, str]:
    """One channel of a run with its axis: ``(axis, x, units of x)``.

    A sampled channel (``"runout/centre/vertical"``) comes with the sample times [s]; a spectrum
    (``"spectrum/centre/vertical"``) with its frequencies ``spectrum/freq_hz`` [Hz]. A channel
    whose length matches neither axis is an error, never paired with the wrong one.
    """
    with h5py.File(path, "r") as f:
        g = _run_group(f, job_id)
        if name not in g or not isinstance(g[name], h5py.Dataset):
            have = []
            g.visititems(lambda n, o: have.append(n) if isinstance(o, h5py.Dataset) else None)
            raise KeyError(f"{job_id}: no channel {name!r} (there are: {', '.join(have)})")
        ds = g[name]
        axis_name = "spectrum/freq_hz" if name.startswith("spectrum/") else "time"
        axis = _read(g[axis_name])
        x = _read(ds)
        if x.shape[:1] != axis.shape[:1]:
            raise ValueError(
                f"{job_id}: channel {name!r} has {x.shape[0]} values but its axis {axis_name!r} "
                f"has {axis.shape[0]}"
            )
        return axis, x, str(_value(ds.attrs.get("units", "")))


def models(path: PathLike) -> dict[str, Model]:
    """The reduced models by model id (a job's ``model_id`` attribute); {} if the file has none."""
    out: dict[str, Model] = {}
    with h5py.File(path, "r") as f:
        for model_id, g in f.get("models", {}).items():
            cols: dict[str, np.ndarray] = {}
            units: dict[str, str] = {}
            for src, dst in (
                ("index", "index"),
                ("freq_hz", "freq_hz"),
                ("labels", "label"),
                ("kinds", "kind"),
                ("strain_energy_share", "strain_energy_share"),
            ):
                if src in g:
                    cols[dst] = _read(g[src])
                    units[dst] = str(_value(g[src].attrs.get("units", "")))
            modes = pd.DataFrame(cols)
            if "index" in modes and bool((modes["index"] % 1 == 0).all()):
                modes["index"] = modes["index"].astype("int64")
            modes.attrs["units"] = units
            out[model_id] = Model(attrs=_attrs(g), modes=modes)
    return out


def job_attrs(path: PathLike) -> pd.DataFrame:
    """Every job's scalar attributes (status, statistics, reference_id, model_id, the overrides
    under their dotted keys, ``label:<key>``, …) as Python values: index job_id in job-index
    order, one column per attribute name (NaN where a job lacks it)."""
    ids = job_ids(path)
    with h5py.File(path, "r") as f:
        rows = {i: _attrs(f["jobs"][i]) for i in ids}
    df = pd.DataFrame.from_dict(rows, orient="index")
    df.index.name = "job_id"
    return df


def job_labels(path: PathLike) -> pd.DataFrame:
    """The jobs' labels on labelled axes: index job_id (job-index order), one str column per
    labelled axis, named by the axis's first key (the jobs' ``label:<key>`` attributes). No
    columns when the study has no labelled axis."""
    labels = job_attrs(path).filter(regex="^label:")
    return labels.rename(columns=lambda c: c.removeprefix("label:"))


def analysis_table(path: PathLike, name: str) -> pd.DataFrame:
    """The ``/analysis/<name>`` table ("lines", "resonances", "trial_mass") with its text columns
    (job_id, channel, label, fixed, …) as ``str``; amplitudes in um, speeds and frequencies in
    Hz, phases in degrees. An empty DataFrame when the file has no such table."""
    with h5py.File(path, "r") as f:
        key = f"analysis/{name}"
        return _table(f[key]) if key in f else pd.DataFrame()


def sweeps(path: PathLike) -> list[Sweep]:
    """The speed sweeps of ``/analysis/sweeps``, by ascending ``n``; [] when there are none."""
    out: list[Sweep] = []
    with h5py.File(path, "r") as f:
        groups = f.get("analysis/sweeps", {})
        for n in sorted(groups, key=int):
            g = groups[n]
            out.append(
                Sweep(
                    n=int(n),
                    fixed=str(_value(g.attrs.get("fixed", ""))),
                    speed_hz=_read(g["speed_hz"]),
                    job_ids=[str(i) for i in _read(g["job_ids"])],
                    orders=_read(g["orders"]),
                    lines=_channel_arrays(g["lines"]),
                    freq_hz=_read(g["freq_hz"]) if "freq_hz" in g else None,
                    maps=_channel_arrays(g["map"]) if "map" in g else {},
                )
            )
    return out
