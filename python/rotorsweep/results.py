"""Read rotorsweep's HDF5 results into pandas DataFrames and xarray Datasets.

A results file (``rotorsweep run STUDY -o OUT.h5``; ``rotorsweep merge`` joins shard files) holds

* file attributes: tool, tool_version, created_utc, host, threads, command, study_name,
  study_path, study_text, varying_keys (newline-separated dotted keys), shard;
* ``/jobs/<job_id>`` and ``/references/<reference_id>``: scalar attributes (status, cause,
  solver statistics, errors against the reference, every override under its dotted key, the
  labels ``label`` and ``label:<key>``) and datasets, each with a ``units`` attribute:
  ``time`` [s], ``runout/<sensor>/{vertical,horizontal}`` [um], optionally ``journal/<node>/{x,y}``
  and ``stand/<node>/{x,y}`` [um], ``contact/<node>/<roller>`` [N], ``modal/<i>``, and after the
  analysis ``spectrum/freq_hz`` [Hz] with ``spectrum/<sensor>/<dir>`` [um];
* ``/models/<model_id>``: the reduced models' modes (``freq_hz``, ``index``, ``labels``, ``kinds``,
  optional ``strain_energy_share``);
* ``/linear/<linear_id>``: Campbell data (``campbell/…`` [speeds × lateral modes]) and, in a
  ``rotorsweep linear -o`` file, unbalance response, Floquet growth, static sag, critical map;
* ``/summary``: one row per job (compound table, units per column);
* ``/analysis``: compound tables ``lines``, ``resonances`` and (with an ``[analysis] baseline``)
  ``trial_mass``; ``sweeps/<n>``, one per set of jobs that differ only in ``speed.hz``, with the
  line amplitudes (speed × order) and the spectral maps (speed × frequency).

The axes (``time``, ``spectrum/freq_hz``, a sweep's ``speed_hz``, ``orders`` and ``freq_hz``) are
HDF5 dimension scales attached to the data they label, so an array always comes with its own
axis here (an array whose axis cannot be found, or does not match its length, is an error, never
paired with another axis). Files from before the scales were written are read by the layout.

``rotorsweep simulate SCENE -o RUN.h5`` writes ``/jobs/<scene name>``; every reader that does not
need ``/summary``, ``/analysis`` or ``/models`` works on it too, and :func:`summary` builds its
row from the job's attributes.

A ``job`` argument is a job id (``"j59ddf536fb970efa"``), a reference id, or a label (the job's
``label`` attribute, or one of its ``label:<key>`` values) that names exactly one job; or a dict of
summary columns and values (``{"label": "100 g", "speed.hz": 14.0}``) that selects one row.

Every function takes a path and opens the file read-only for the duration of the call.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any, TypedDict, Union

import h5py
import numpy as np
import pandas as pd
import xarray as xr

PathLike = Union[str, "os.PathLike[str]"]
#: A job as the readers take it: an id, a label, or a dict of summary columns and values.
JobRef = Union[str, Mapping[str, Any]]

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
    "factorizations",
    "events",
)

#: The channel families of a run and the axis each is sampled along (by name: files from
#: before the dimension scales find it by layout, :func:`_layout_axis`).
_FAMILIES = {
    "runout": "time",
    "journal": "time",
    "stand": "time",
    "contact": "time",
    "modal": "time",
    "spectrum": "freq_hz",
}


class Job(TypedDict):
    """One run as :func:`load_job` returns it."""

    id: str
    #: "jobs" or "references".
    group: str
    #: Scalar attributes as Python values (str, int, float; NaN where the file has NaN).
    attrs: dict[str, Any]
    #: Datasets by path relative to the run's group, e.g. "time", "runout/centre/vertical" (each
    #: dataset once: the axes linked beside their data, "runout/centre/time", are left out).
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


# --- low-level: attributes, datasets, tables -------------------------------------------------


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
    # The dimension-scale bookkeeping (CLASS, NAME, REFERENCE_LIST, DIMENSION_LIST) is no data.
    skip = {"CLASS", "NAME", "REFERENCE_LIST", "DIMENSION_LIST"}
    return {k: _value(v) for k, v in obj.attrs.items() if k not in skip}


def _units(obj: h5py.HLObject) -> str:
    return str(_value(obj.attrs.get("units", "")))


def _read(ds: h5py.Dataset) -> np.ndarray:
    """A dataset as a numpy array; variable-length strings as an object array of str."""
    if h5py.check_string_dtype(ds.dtype) is not None:
        return np.asarray(ds.asstr()[()], dtype=object)
    return np.asarray(ds[()])


def _is_scale(ds: h5py.Dataset) -> bool:
    return bool(h5py.h5ds.is_scale(ds.id))


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
            df[name] = pd.Series(
                [b.decode("utf-8", "replace") if isinstance(b, bytes) else b for b in table[name]]
            )
    df.attrs["units"] = {
        name: str(_value(ds.attrs[f"units:{name}"]))
        for name in table.dtype.names or ()
        if f"units:{name}" in ds.attrs
    }
    return df


def _datasets(g: h5py.Group) -> dict[str, h5py.Dataset]:
    """The datasets below ``g`` by relative path, each once: an axis hard-linked beside its data
    (``runout/centre/time`` is ``time``) is listed at its own place only."""
    out: dict[str, h5py.Dataset] = {}

    def walk(grp: h5py.Group, prefix: str, above: list[h5py.Group]) -> None:
        for name, obj in grp.items():
            if isinstance(obj, h5py.Group):
                walk(obj, f"{prefix}{name}/", [*above, grp])
            elif isinstance(obj, h5py.Dataset):
                if _is_scale(obj) and any(
                    isinstance(a.get(name), h5py.Dataset) and a[name] == obj for a in above
                ):
                    continue
                out[f"{prefix}{name}"] = obj

    walk(g, "", [])
    return out


def _axis(ds: h5py.Dataset, dim: int, fallback: h5py.Dataset | None) -> h5py.Dataset:
    """The axis of dimension ``dim`` of ``ds``: its attached dimension scale, else (files from
    before the scales) ``fallback``; its length must be the dataset's there."""
    attached = ds.dims[dim]
    axis = attached[0] if len(attached) else fallback
    if axis is None:
        raise ValueError(f"{ds.file.filename}:{ds.name}: no axis for dimension {dim}")
    if axis.shape[:1] != ds.shape[dim : dim + 1]:
        raise ValueError(
            f"{ds.file.filename}:{ds.name} has {ds.shape[dim]} values along dimension {dim} "
            f"but its axis {axis.name} has {axis.shape[0]}"
        )
    return axis


def _coord(axis: h5py.Dataset, name: str) -> xr.Variable:
    return xr.Variable(name, _read(axis), attrs={"units": _units(axis)})


# --- runs and their lookup ---------------------------------------------------------------------


def _run_group(f: h5py.File, run_id: str) -> h5py.Group | None:
    for name in RUN_GROUPS:
        if name in f and run_id in f[name] and isinstance(f[name][run_id], h5py.Group):
            return f[name][run_id]
    return None


def _known(f: h5py.File) -> str:
    known = [i for name in RUN_GROUPS if name in f for i in f[name]]
    return (", ".join(known[:8]) + (", …" if len(known) > 8 else "")) or "none"


def _resolve(f: h5py.File, job: JobRef) -> h5py.Group:
    """The group of ``job`` (module doc: an id, a label or a dict of summary values)."""
    where = f.filename
    if isinstance(job, Mapping):
        if not job:
            raise ValueError(f"{where}: an empty dict selects no one job: give summary columns and values")
        df = _summary(f)
        mask = pd.Series(True, index=df.index)
        for key, want in job.items():
            if key not in df:
                raise KeyError(f"{where}: the summary has no column {key!r} (columns: {', '.join(df)})")
            col = df[key]
            mask &= np.isclose(col.astype(float), float(want)) if _numeric(col, want) else col == want
        ids = list(df.loc[mask, "job_id"])
        what = "with " + ", ".join(f"{k}={v!r}" for k, v in job.items())
    else:
        if not isinstance(job, str):
            raise TypeError(f"job must be a job id, a label or a dict of summary values, not {type(job).__name__}")
        g = _run_group(f, job)
        if g is not None:
            return g
        ids = [
            i
            for i, run in f.get("jobs", {}).items()
            if job == _value(run.attrs.get("label", None))
            or any(k.startswith("label:") and _value(v) == job for k, v in run.attrs.items())
        ]
        what = f"with id or label {job!r}"
    if len(ids) == 1:
        return f["jobs"][ids[0]]
    if not ids:
        raise KeyError(f"{where}: no job or reference {what} (there are: {_known(f)})")
    shown = ", ".join(ids[:8]) + (", …" if len(ids) > 8 else "")
    raise KeyError(
        f"{where}: {len(ids)} jobs {what} ({shown}): give the id, or a dict such as "
        f"{{'label': …, 'speed.hz': …}}"
    )


def _numeric(col: pd.Series, want: Any) -> bool:
    return isinstance(want, (int, float, np.number)) and not isinstance(want, bool) and pd.api.types.is_numeric_dtype(col)


def job_id(path: PathLike, job: JobRef) -> str:
    """The id of ``job`` (an id, a label or a dict of summary values; module doc)."""
    with h5py.File(path, "r") as f:
        return _resolve(f, job).name.split("/")[-1]


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


# --- tables ------------------------------------------------------------------------------------

#: Units by the suffix a statistic's or parameter's name states (for a file without /summary).
_SUFFIX_UNITS = (("_um", "um"), ("_hz", "Hz"), ("_s", "s"), (".hz", "Hz"), ("_mm", "mm"), ("_kg", "kg"))


def _summary(f: h5py.File) -> pd.DataFrame:
    if "summary" in f:
        df = _table(f["summary"])
        # A varying solver.integrator is stored only as the "integrator" column; give it its
        # dotted key too, so that df[varying_keys(path)] works.
        varying = str(_value(f.attrs.get("varying_keys", ""))).split("\n")
        if "solver.integrator" in varying and "solver.integrator" not in df and "integrator" in df:
            df["solver.integrator"] = df["integrator"]
            df.attrs["units"]["solver.integrator"] = ""
    else:
        rows = [{"job_id": i, **_attrs(g)} for i, g in f.get("jobs", {}).items()]
        df = pd.DataFrame(rows)
        units: dict[str, str] = {}
        for c in df:
            if df[c].map(lambda v: isinstance(v, str)).all():
                units[c] = ""
            elif c in COUNT_COLUMNS or pd.api.types.is_integer_dtype(df[c]):
                units[c] = "1"
            else:
                units[c] = next((u for s, u in _SUFFIX_UNITS if c.endswith(s)), "1")
        df.attrs["units"] = units
    units = df.attrs["units"]
    for name in COUNT_COLUMNS:
        if name in df:
            col = pd.to_numeric(df[name], errors="coerce")
            if bool((col.dropna() % 1 == 0).all()):
                df[name] = col.astype("Int64")
    df.attrs["units"] = units
    return df


def summary(path: PathLike, *, index: bool = False) -> pd.DataFrame:
    """The ``/summary`` table: one row per job, in job-index order.

    Text columns (job_id, status, cause, error_cause, integrator, modes, label, text parameters)
    are ``str`` (``df.status == "ok"`` works); the counts in :data:`COUNT_COLUMNS` are integers
    (pandas' nullable Int64); ``df.attrs["units"]`` maps every column to its units (``""`` for
    text, ``"1"`` for counts and pure numbers). Varying parameters keep their dotted names
    (``df["speed.hz"]``; in ``DataFrame.query`` write them in backticks); a varying
    ``solver.integrator``, which the file keeps only as the ``integrator`` column, is also given
    its dotted key. With ``index=True`` job_id is the index, otherwise a column. A file without
    ``/summary`` (``rotorsweep simulate``) gets one row per run built from the runs' attributes,
    with units from the names' suffixes (``_s``, ``_hz``, ``_um``).
    """
    with h5py.File(path, "r") as f:
        df = _summary(f)
    if index and "job_id" in df:
        units = df.attrs["units"]
        df = df.set_index("job_id")
        df.attrs["units"] = units
    return df


def analysis(path: PathLike, name: str) -> pd.DataFrame:
    """The ``/analysis/<name>`` table ("lines", "resonances", "trial_mass") with its text columns
    (job_id, channel, label, fixed, …) as ``str`` and ``df.attrs["units"]`` (amplitudes in um,
    speeds and frequencies in Hz, phases in degrees). An empty DataFrame when the file has no
    such table."""
    with h5py.File(path, "r") as f:
        key = f"analysis/{name}"
        if key in f:
            return _table(f[key])
        df = pd.DataFrame()
        df.attrs["units"] = {}
        return df


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
                    units[dst] = _units(g[src])
            modes = pd.DataFrame(cols)
            if "index" in modes and bool((modes["index"] % 1 == 0).all()):
                modes["index"] = modes["index"].astype("int64")
            modes.attrs["units"] = units
            out[model_id] = Model(attrs=_attrs(g), modes=modes)
    return out


# --- one run: datasets and xarray channels -----------------------------------------------------


def load_job(path: PathLike, job: JobRef) -> Job:
    """One run (from ``/jobs``, else ``/references``): attributes, datasets and their units."""
    with h5py.File(path, "r") as f:
        g = _resolve(f, job)
        ds = _datasets(g)
        return Job(
            id=g.name.split("/")[-1],
            group=g.parent.name.strip("/"),
            attrs=_attrs(g),
            data={k: _read(v) for k, v in ds.items()},
            units={k: _units(v) for k, v in ds.items()},
        )


def channels(path: PathLike, job: JobRef) -> list[str]:
    """Names of a run's channels (every dataset but the axes), e.g. "runout/drive/vertical",
    "spectrum/centre/vertical"."""
    with h5py.File(path, "r") as f:
        have = _datasets(_resolve(f, job))
        # The axes: dimension scales, and by name in files from before the scales.
        return [k for k, d in have.items() if not _is_scale(d) and k not in ("time", "spectrum/freq_hz")]


def _layout_axis(g: h5py.Group, family: str) -> h5py.Dataset | None:
    """The axis of a channel family by the layout (``time``; ``spectrum/freq_hz``), if present."""
    name = _FAMILIES.get(family, "time")
    path = "time" if name == "time" else f"{family}/{name}"
    return g[path] if path in g else None


def _family(g: h5py.Group, family: str) -> xr.Dataset:
    """The channels ``family/<place>/<leaf>`` of a run as one Dataset: one variable per leaf
    (vertical, horizontal; x, y; a roller) over (sensor or node, axis), the axis from the
    datasets' own dimension scales."""
    where = f"{g.file.filename}:{g.name}"
    if family not in g:
        have = ", ".join(k for k in g if isinstance(g[k], h5py.Group)) or "none"
        extra = " (the study analysis writes spectra; this run was not analysed)" if family == "spectrum" else ""
        raise KeyError(f"{where}: no {family} channels{extra} (families there: {have})")
    axis_name = _FAMILIES[family]
    fallback = _layout_axis(g, family)
    places = [p for p, obj in g[family].items() if isinstance(obj, h5py.Group)]
    leaves: list[str] = []
    for p in places:
        for leaf, obj in g[family][p].items():
            if isinstance(obj, h5py.Dataset) and not _is_scale(obj) and leaf not in leaves:
                leaves.append(leaf)
    if not places or not leaves:
        raise KeyError(f"{where}: {family} holds no channels")
    axis = None
    data: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for leaf in leaves:
        rows = []
        for p in places:
            ds = g[family][p].get(leaf)
            if ds is None:
                rows.append(None)
                continue
            a = _axis(ds, 0, fallback)
            if axis is None:
                axis = a
            elif a.shape != axis.shape or not np.array_equal(a[()], axis[()]):
                raise ValueError(f"{where}: {family}/{p}/{leaf} has another {axis_name} axis than {axis.name}")
            rows.append(_read(ds).astype(float))
            units[leaf] = _units(ds)
        assert axis is not None
        n = axis.shape[0]
        data[leaf] = np.stack([r if r is not None else np.full(n, np.nan) for r in rows])
    assert axis is not None
    dim = "sensor" if family in ("runout", "spectrum") else "node"
    coords = {dim: places, axis_name: _coord(axis, axis_name)}
    out = xr.Dataset(
        {leaf: ((dim, axis_name), v, {"units": units[leaf]}) for leaf, v in data.items()},
        coords=coords,
    )
    out.attrs = {"job_id": g.name.split("/")[-1], **{k: v for k, v in _attrs(g).items() if isinstance(v, (str, int, float))}}
    return out


def _family_of(path: PathLike, job: JobRef, family: str) -> xr.Dataset:
    with h5py.File(path, "r") as f:
        return _family(_resolve(f, job), family)


def runout(path: PathLike, job: JobRef) -> xr.Dataset:
    """A run's runout: variables ``vertical`` and ``horizontal`` [um] over (sensor, time), the
    coordinate ``time`` in seconds (``units`` attributes); the run's attributes in ``attrs``.
    ``runout(path, job).vertical.sel(sensor="centre")`` is one series."""
    return _family_of(path, job, "runout")


def spectrum(path: PathLike, job: JobRef) -> xr.Dataset:
    """A run's runout spectrum (amplitude-correct Hanning, written by the study analysis):
    ``vertical`` and ``horizontal`` [um] over (sensor, freq_hz), ``freq_hz`` in Hz."""
    return _family_of(path, job, "spectrum")


def orbits(path: PathLike, job: JobRef, where: str = "journal") -> xr.Dataset:
    """Journal (``where="journal"``) or stand (``"stand"``) motion in the inertial frame: ``x``
    and ``y`` [um] over (node, time). Written when the scene asks for them
    (``outputs.journal_orbits``, ``outputs.stand_motion``)."""
    if where not in ("journal", "stand"):
        raise ValueError(f"orbits: where is 'journal' or 'stand', not {where!r}")
    return _family_of(path, job, where)


def contact_forces(path: PathLike, job: JobRef) -> xr.Dataset:
    """Roller contact forces [N] (``outputs.contact_forces``): one variable per roller over
    (node, time); 0 is lift-off."""
    return _family_of(path, job, "contact")


def nip_forces(path: PathLike, job: JobRef, *, nip: str, quantity: str = "force") -> xr.DataArray:
    """A nip's segment forces [N] (``quantity="force"``) or band widths [mm] (``"width"``, for
    the hertz and cover laws) of a machine's run, over (``z_mm``, ``time``): the segment
    centres along the rolls [mm] and the sample times [s], each a coordinate with its units.
    ``nip_forces(path, job, nip="main").sum("z_mm")`` is the nip's total force over time.
    ``attrs`` hold ``units`` and, in files that record them, the nip's rolls ``roll_a``,
    ``roll_b`` (names) and their speeds ``speed_a_hz``, ``speed_b_hz`` [Hz] (a roll's runout
    orders lie at k times its own speed)."""
    if quantity not in ("force", "width"):
        raise ValueError(f"nip_forces: quantity is 'force' or 'width', not {quantity!r}")
    with h5py.File(path, "r") as f:
        g = _resolve(f, job)
        nips = g.get("nips")
        if nips is None or nip not in nips:
            have = ", ".join(nips) if nips is not None else "none: not a machine's run"
            raise KeyError(f"{g.name}: no nip {nip!r} (nips: {have})")
        if quantity not in nips[nip]:
            raise KeyError(f"{g.name}/nips/{nip}: no {quantity!r} (a linear nip has no band width)")
        ds = nips[nip][quantity]
        z, t = _axis(ds, 0, None), _axis(ds, 1, None)
        attrs = {"units": _units(ds)}
        for side in ("a", "b"):
            name, speed = g.attrs.get(f"nip_roll_{side}:{nip}"), g.attrs.get(f"nip_speed_{side}_hz:{nip}")
            if name is not None and speed is not None:
                attrs[f"roll_{side}"] = name.decode() if isinstance(name, bytes) else str(name)
                attrs[f"speed_{side}_hz"] = float(speed)
        return xr.DataArray(
            _read(ds),
            dims=("z_mm", "time"),
            coords={"z_mm": _coord(z, "z_mm"), "time": _coord(t, "time")},
            name=f"nips/{nip}/{quantity}",
            attrs=attrs,
        )


def channel(path: PathLike, job: JobRef, name: str) -> xr.DataArray:
    """One dataset of a run with its own axis, e.g. ``"runout/centre/vertical"`` over ``time``
    [s] or ``"spectrum/centre/vertical"`` over ``freq_hz`` [Hz]. A channel whose axis is
    missing or of another length is an error, never paired with the wrong one."""
    with h5py.File(path, "r") as f:
        g = _resolve(f, job)
        have = _datasets(g)
        if name not in have:
            raise KeyError(f"{g.name}: no channel {name!r} (there are: {', '.join(have)})")
        ds = have[name]
        fallback = _layout_axis(g, name.split("/")[0]) if ds.ndim == 1 else None
        axis = _axis(ds, 0, fallback)
        dim = axis.name.split("/")[-1]
        return xr.DataArray(
            _read(ds), dims=(dim,), coords={dim: _coord(axis, dim)}, name=name, attrs={"units": _units(ds)}
        )


# --- sweeps ------------------------------------------------------------------------------------


def _channel_arrays(g: h5py.Group) -> dict[str, np.ndarray]:
    """The datasets ``<sensor>/<dir>`` under ``g`` by channel name ("centre/vertical", …)."""
    return {k: _read(d) for k, d in _datasets(g).items() if not _is_scale(d)}


def sweeps(path: PathLike) -> list[Sweep]:
    """The speed sweeps of ``/analysis/sweeps`` as numpy arrays, by ascending ``n``; [] when
    there are none. :func:`spectral_map` and :func:`line_amplitudes` give them as xarray."""
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
                    lines=_channel_arrays(g["lines"]) if "lines" in g else {},
                    freq_hz=_read(g["freq_hz"]) if "freq_hz" in g else None,
                    maps=_channel_arrays(g["map"]) if "map" in g else {},
                )
            )
    return out


def _sweep_group(f: h5py.File, n: int) -> h5py.Group:
    key = f"analysis/sweeps/{n}"
    if key not in f:
        have = ", ".join(sorted(f.get("analysis/sweeps", {}), key=int)) or "none"
        raise KeyError(f"{f.filename}: no sweep {n} (sweeps: {have}; a sweep is ≥ 3 jobs differing only in speed.hz)")
    return f[key]


def _sweep_dataset(g: h5py.Group, part: str, second: str, dim2: str) -> xr.Dataset:
    where = f"{g.file.filename}:{g.name}"
    if part not in g:
        raise KeyError(f"{where}: no {part} (the records' lengths or rates differ)" if part == "map" else f"{where}: no {part}")
    sensors = [s for s, obj in g[part].items() if isinstance(obj, h5py.Group)]
    leaves = ["vertical", "horizontal"]
    speed = _coord(g["speed_hz"], "speed_hz")
    axis2 = None
    data = {}
    units = {}
    for leaf in leaves:
        rows = []
        for s in sensors:
            ds = g[part][s][leaf]
            _axis(ds, 0, g["speed_hz"])
            a = _axis(ds, 1, g[second])
            axis2 = a if axis2 is None else axis2
            rows.append(_read(ds))
            units[leaf] = _units(ds)
        data[leaf] = np.stack(rows)
    assert axis2 is not None
    out = xr.Dataset(
        {leaf: (("sensor", "speed_hz", dim2), v, {"units": units[leaf]}) for leaf, v in data.items()},
        coords={
            "sensor": sensors,
            "speed_hz": speed,
            dim2: _coord(axis2, dim2),
            "job_id": ("speed_hz", [str(i) for i in _read(g["job_ids"])]),
        },
    )
    out.attrs = {"sweep": int(g.name.split("/")[-1]), "fixed": str(_value(g.attrs.get("fixed", "")))}
    return out


def spectral_map(path: PathLike, sweep: int = 0) -> xr.Dataset:
    """Sweep ``sweep``'s spectral map: ``vertical`` and ``horizontal`` [um] over (sensor,
    speed_hz, freq_hz), both axes in Hz, ``job_id`` along speed_hz, ``attrs["fixed"]`` the other
    keys' values. ``spectral_map(path).vertical.sel(sensor="centre")`` is one map."""
    with h5py.File(path, "r") as f:
        return _sweep_dataset(_sweep_group(f, sweep), "map", "freq_hz", "freq_hz")


def line_amplitudes(path: PathLike, sweep: int = 0) -> xr.Dataset:
    """Sweep ``sweep``'s line amplitudes: ``vertical`` and ``horizontal`` [um] over (sensor,
    speed_hz, order), the amplitude at order × speed."""
    with h5py.File(path, "r") as f:
        return _sweep_dataset(_sweep_group(f, sweep), "lines", "orders", "order")


# --- linear systems ----------------------------------------------------------------------------


def linear_systems(path: PathLike) -> list[str]:
    """The ids of ``/linear/<id>`` (a study's ``linear_id``; the scene name in a ``rotorsweep
    linear -o`` file)."""
    with h5py.File(path, "r") as f:
        return sorted(f.get("linear", {}))


def _linear_group(f: h5py.File, system: str | None) -> h5py.Group:
    have = sorted(f.get("linear", {}))
    if system is None:
        if len(have) != 1:
            raise KeyError(f"{f.filename}: {len(have)} linear systems ({', '.join(have) or 'none'}): name one")
        system = have[0]
    if system not in have:
        raise KeyError(f"{f.filename}: no linear system {system!r} (there are: {', '.join(have) or 'none'})")
    return f["linear"][system]


def campbell(path: PathLike, system: str | None = None) -> xr.Dataset:
    """The Campbell data of a linear system (``/linear/<system>``; the only one when None):
    ``whirl_hz`` [Hz], ``log_dec``, ``damping_ratio``, ``whirl_index``, ``whirl`` (1 forward, −1
    backward, 0 mixed) and ``branch`` (−1: none) over (speed_hz, mode), mode the k-th lowest
    lateral mode at each speed; the critical speeds ``critical_speed_hz`` with
    ``critical_log_dec`` and ``critical_whirl`` over ``critical``; with a ``rotorsweep linear -o``
    file also the unbalance response ``unbalance_amplitude`` [um] and ``unbalance_phase`` [deg]
    over (sensor, direction, speed_hz). Attributes: the group's (``stability_threshold_hz`` when
    a speed is unstable, ``vertical_hz``, ``horizontal_hz``, ``frame``)."""
    with h5py.File(path, "r") as f:
        g = _linear_group(f, system)
        c = g["campbell"]
        speed = c["speed_hz"]
        variables: dict[str, Any] = {}
        for name in ("whirl_hz", "log_dec", "damping_ratio", "whirl_index", "whirl", "branch"):
            if name in c:
                ds = c[name]
                _axis(ds, 0, speed)
                attrs = {"units": _units(ds)}
                if "codes" in ds.attrs:
                    attrs["codes"] = str(_value(ds.attrs["codes"]))
                variables[name] = (("speed_hz", "mode"), _read(ds), attrs)
        for name, dst in (("critical_speeds_hz", "critical_speed_hz"), ("critical_log_dec", "critical_log_dec"), ("critical_whirl", "critical_whirl")):
            if name in g:
                variables[dst] = ("critical", _read(g[name]), {"units": _units(g[name])})
        if "unbalance_response" in g:
            ur = g["unbalance_response"]
            sensors = list(ur)
            dirs = ["vertical", "horizontal"]
            for leaf, dst in (("amplitude_um", "unbalance_amplitude"), ("phase_deg", "unbalance_phase")):
                arr = np.stack([np.stack([_read(ur[s][d][leaf]) for d in dirs]) for s in sensors])
                if arr.shape[-1] != speed.shape[0]:
                    raise ValueError(f"{g.name}/unbalance_response: {arr.shape[-1]} speeds, the Campbell has {speed.shape[0]}")
                variables[dst] = (("sensor", "direction", "speed_hz"), arr, {"units": _units(ur[sensors[0]][dirs[0]][leaf])})
            coords_extra = {"sensor": sensors, "direction": dirs}
        else:
            coords_extra = {}
        nb = c["whirl_hz"].shape[1] if "whirl_hz" in c else 0
        out = xr.Dataset(
            variables,
            coords={"speed_hz": _coord(speed, "speed_hz"), "mode": np.arange(nb), **coords_extra},
        )
        out.attrs = {k: v for k, v in _attrs(g).items() if isinstance(v, (str, int, float))}
        out.attrs["system"] = g.name.split("/")[-1]
        return out


# Older names (of the former scripts/rotorsweep_py), kept so that scripts written against them run.
load_summary = summary
analysis_table = analysis
