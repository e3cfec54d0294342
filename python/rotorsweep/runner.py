"""Drive the rotorsweep binary from Python: ``modes``, ``linear``, ``simulate`` and ``run``.

>>> import rotorsweep as rs
>>> s = rs.Scene("studies/scenes/reference-roll.toml").set("roll.shell.outer_diameter_mm", 300.0)
>>> m = rs.modes(s)                                # DataFrame of the kept modes (as rs.models)
>>> c = rs.linear(s, speeds="0:60:61")             # xarray Campbell data (as rs.campbell)
>>> r = rs.simulate(s, set={"simulation.t_end_s": 0.2})   # xarray runout (as rs.runout)
>>> df = rs.run("studies/smoke.toml", output="smoke.h5")  # DataFrame (as rs.summary)

In: a scene (a :class:`rotorsweep.Scene`, whose overrides become ``--set`` arguments, or a path)
or a study path, and keyword arguments that map to the command's flags (``speed_hz=16.4`` →
``--speed-hz 16.4``; ``set={"speed.hz": 14.0}`` → ``--set speed.hz=14.0``; a flag given True is
passed bare). Out: what the package's readers return for the file the command writes (``-o``
into ``output``, or into a temporary folder removed afterwards): :func:`~rotorsweep.campbell`,
:func:`~rotorsweep.runout`, :func:`~rotorsweep.summary`; ``modes``, which writes no file, gives
its ``--json`` as the modes table of :func:`~rotorsweep.models`.

The binary is ``binary=`` if given, else ``$ROTORSWEEP_BIN``, else ``rotorsweep`` on ``PATH``,
else ``target/release/rotorsweep`` of the source tree the package lies in or of the current
folder or one above it. Every call has a ``timeout`` [s] (default :data:`DEFAULT_TIMEOUT`; None:
none) after which the binary is killed and :class:`RotorsweepTimeout` raised. A failed command
raises :class:`RotorsweepError` with the binary's message (its standard error) and exit code
(docs/cli.md: 1 input error, 64 usage, 74 I/O, 75 output in use). Exit code 2 of ``simulate`` and
``run`` (done, but a run did not end ok: its status says why) returns the results with a
:class:`RotorsweepWarning`.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
import warnings
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Union

import pandas as pd
import xarray as xr

from . import results

if TYPE_CHECKING:
    from .scene import Scene

PathLike = Union[str, "os.PathLike[str]"]
#: A scene as the runners take it.
SceneLike = Union["Scene", str, "os.PathLike[str]"]

#: Seconds a command may run by default before it is killed.
DEFAULT_TIMEOUT = 3600.0
#: Exit code of a command that finished but some run did not end ok (docs/cli.md).
EXIT_NOT_OK = 2


class RotorsweepError(RuntimeError):
    """The binary failed: ``message`` (its standard error, stripped), ``returncode`` (None when
    it was killed or could not start), ``stderr`` in full and ``command`` (argv)."""

    def __init__(
        self,
        message: str,
        *,
        returncode: int | None = None,
        stderr: str = "",
        command: Sequence[str] = (),
    ) -> None:
        super().__init__(message)
        self.message = message
        self.returncode = returncode
        self.stderr = stderr
        self.command = list(command)

    def __str__(self) -> str:
        return self.message


class RotorsweepTimeout(RotorsweepError, TimeoutError):
    """The binary ran longer than its ``timeout`` and was killed."""


class RotorsweepWarning(UserWarning):
    """The command finished, but a run did not end ok (exit code 2); the results are returned."""


# --- the binary --------------------------------------------------------------------------------


def _tree_binaries() -> list[Path]:
    """``target/release/rotorsweep`` of the source tree holding this package (an editable or
    in-place install) and of the current folder and those above it."""
    here = Path(__file__).resolve()
    roots = [here.parents[2], Path.cwd(), *Path.cwd().parents]
    return [r / "target" / "release" / "rotorsweep" for r in roots if (r / "Cargo.toml").is_file()]


def find_binary(binary: PathLike | None = None) -> Path:
    """The rotorsweep binary the runners use (module doc); :class:`RotorsweepError` if none."""
    return _find_binary(binary)


def _find_binary(binary: PathLike | None = None) -> Path:
    if binary is not None:
        tried = [Path(binary)]
    elif os.environ.get("ROTORSWEEP_BIN"):
        tried = [Path(os.environ["ROTORSWEEP_BIN"])]
    else:
        on_path = shutil.which("rotorsweep")
        tried = [Path(on_path)] if on_path else []
        tried += _tree_binaries()
    for b in tried:
        if b.is_file() and os.access(b, os.X_OK):
            return b.absolute()
    where = ", ".join(map(str, tried)) or "nothing"
    raise RotorsweepError(
        "no rotorsweep binary (tried binary=, $ROTORSWEEP_BIN, rotorsweep on PATH, the source "
        f"tree's target/release/rotorsweep: {where}); build it with `cargo build --release` or "
        "set ROTORSWEEP_BIN"
    )


def _invoke(
    binary: Path,
    args: Sequence[str],
    *,
    timeout: float | None,
    ok: Iterable[int] = (0,),
    cwd: PathLike | None = None,
) -> subprocess.CompletedProcess[str]:
    """Runs ``binary args``; its output as text. A timeout kills it (:class:`RotorsweepTimeout`);
    an exit code outside ``ok`` is a :class:`RotorsweepError` with its standard error."""
    argv = [str(binary), *map(str, args)]
    try:
        p = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, cwd=cwd, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired as e:
        err = e.stderr.decode("utf-8", "replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
        raise RotorsweepTimeout(
            f"rotorsweep {args[0]} did not finish within {timeout} s and was killed", stderr=err, command=argv
        ) from None
    except OSError as e:
        raise RotorsweepError(f"cannot start {binary}: {e}", command=argv) from e
    if p.returncode not in tuple(ok):
        message = p.stderr.strip() or p.stdout.strip() or f"rotorsweep {args[0]} failed"
        raise RotorsweepError(
            f"{message} (exit code {p.returncode})", returncode=p.returncode, stderr=p.stderr, command=argv
        )
    return p


# --- arguments ---------------------------------------------------------------------------------


def _scene_args(
    scene: SceneLike, set: Mapping[str, Any] | Sequence[str] | None, binary: PathLike | None
) -> tuple[Path, list[str]]:
    """The binary (``binary``, else a Scene's own, else found) and the arguments that name the
    scene: its path and ``--set`` arguments (a Scene's overrides, then ``set``)."""
    from .scene import Scene, toml_value

    if isinstance(scene, Scene):
        path, overrides = scene.path, list(scene.overrides)
        binary = binary if binary is not None else scene.binary
    else:
        path, overrides = Path(scene), []
    if isinstance(set, Mapping):
        overrides += [f"{k}={toml_value(v)}" for k, v in set.items()]
    elif set is not None:
        if isinstance(set, str):
            raise TypeError("set: a dict {key: value} or a list of 'key=value' strings, not one str")
        overrides += list(set)
    args = [str(path)]
    for o in overrides:
        args += ["--set", o]
    return _find_binary(binary), args


def _flags(**kwargs: Any) -> list[str]:
    """``name=value`` as ``--name value`` (underscores as dashes); True as a bare flag; None and
    False left out; a list or tuple as comma-separated values."""
    out: list[str] = []
    for name, value in kwargs.items():
        flag = "--" + name.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            out.append(flag)
        elif isinstance(value, (list, tuple)):
            out += [flag, ",".join(map(str, value))]
        else:
            out += [flag, str(value)]
    return out


class _Output:
    """Where a command writes: ``output`` (kept), or a file in a temporary folder removed on
    exit."""

    def __init__(self, output: PathLike | None, name: str) -> None:
        self._tmp = tempfile.TemporaryDirectory(prefix="rotorsweep-") if output is None else None
        self.path = Path(self._tmp.name) / name if self._tmp else Path(output).absolute()  # type: ignore[arg-type]

    def __enter__(self) -> Path:
        return self.path

    def __exit__(self, *exc: object) -> None:
        if self._tmp is not None:
            self._tmp.cleanup()


def _written(p: subprocess.CompletedProcess[str], out: Path) -> None:
    """A command that ended with exit code 2 but wrote no results is an error."""
    if not out.is_file():
        raise RotorsweepError(
            f"{p.stderr.strip() or 'rotorsweep ' + p.args[1] + ' wrote no results'} (exit code {p.returncode}; no {out})",
            returncode=p.returncode,
            stderr=p.stderr,
            command=p.args,
        )


def _warn_not_ok(p: subprocess.CompletedProcess[str], what: str) -> None:
    if p.returncode == EXIT_NOT_OK:
        detail = p.stderr.strip()
        warnings.warn(
            f"rotorsweep {what}: a run did not end ok (exit code 2){': ' + detail if detail else ''}",
            RotorsweepWarning,
            stacklevel=3,
        )


# --- the commands ------------------------------------------------------------------------------


def modes(
    scene: SceneLike,
    *,
    modes: str | None = None,
    speed_hz: float | None = None,
    max_speed_hz: float | None = None,
    set: Mapping[str, Any] | Sequence[str] | None = None,
    timeout: float | None = DEFAULT_TIMEOUT,
    binary: PathLike | None = None,
) -> pd.DataFrame:
    """``rotorsweep modes SCENE --json``: the kept modes of the reduced model as
    :func:`rotorsweep.models` gives them (columns index, freq_hz [Hz], label, kind;
    ``df.attrs["units"]``), and in ``df.attrs`` the rest of the JSON object under its names:
    ``scene``, ``mass_kg``, ``balancing_masses``, ``elements``, ``nodes``, ``dofs``,
    ``modes_selected``, ``build_time_s``, ``speed_hz``, ``supported_hz`` (``vertical``,
    ``horizontal``: lists [Hz] on the linearised supports at standstill), ``whirl_hz`` (at
    ``speed_hz``), ``critical_speeds_hz`` (None with ``speed_hz`` alone), ``frame``,
    ``warnings``. ``modes`` ("30n+12st", "0-4,7"), ``speed_hz`` and ``max_speed_hz`` are the
    command's flags."""
    exe, args = _scene_args(scene, set, binary)
    p = _invoke(
        exe,
        ["modes", *args, *_flags(modes=modes, speed_hz=speed_hz, max_speed_hz=max_speed_hz), "--json"],
        timeout=timeout,
    )
    return _modes_frame(json.loads(p.stdout))


def _modes_frame(report: dict[str, Any]) -> pd.DataFrame:
    report = dict(report)
    rows = report.pop("modes", [])
    df = pd.DataFrame(rows, columns=list(rows[0]) if rows else ["index", "freq_hz", "label", "kind"])
    df["index"] = df["index"].astype("int64")
    df["freq_hz"] = df["freq_hz"].astype(float)
    for c in ("label", "kind"):
        df[c] = df[c].astype(str)
    units = {"index": "1", "freq_hz": "Hz", "label": "", "kind": "", "strain_energy_share": "1"}
    df.attrs["units"] = {c: units.get(c, "") for c in df}
    df.attrs.update(report)
    return df


def linear(
    scene: SceneLike,
    *,
    output: PathLike | None = None,
    overwrite: bool = False,
    speed_hz: float | None = None,
    speeds: str | Sequence[float] | None = None,
    modes: str | None = None,
    max_freq_hz: float | None = None,
    unbalance: str | Sequence[float] | None = None,
    floquet_cutoff_hz: float | None = None,
    shapes: bool = False,
    set: Mapping[str, Any] | Sequence[str] | None = None,
    timeout: float | None = DEFAULT_TIMEOUT,
    binary: PathLike | None = None,
) -> xr.Dataset:
    """``rotorsweep linear SCENE -o OUT.h5``: the Campbell data as :func:`rotorsweep.campbell`
    reads them from that file (whirl frequencies, log decrements, whirl direction over
    (speed_hz, mode), critical speeds, unbalance response). ``output`` keeps the file (the
    other readers and ``python -m rotorsweep.figures`` take it); without it a temporary file is
    read and removed. ``speeds`` is "START:STOP:COUNT" or (start, stop, count);
    ``unbalance`` "MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM" or those four numbers."""
    if speeds is not None and not isinstance(speeds, str):
        start, stop, count = speeds
        speeds = f"{start}:{stop}:{int(count)}"
    exe, args = _scene_args(scene, set, binary)
    flags = _flags(
        speed_hz=speed_hz,
        speeds=speeds,
        modes=modes,
        max_freq_hz=max_freq_hz,
        unbalance=unbalance,
        floquet_cutoff_hz=floquet_cutoff_hz,
        shapes=shapes,
        overwrite=overwrite,
    )
    with _Output(output, "linear.h5") as out:
        _invoke(exe, ["linear", *args, *flags, "-o", str(out)], timeout=timeout)
        return results.campbell(out)


def simulate(
    scene: SceneLike,
    *,
    output: PathLike | None = None,
    overwrite: bool = False,
    set: Mapping[str, Any] | Sequence[str] | None = None,
    timeout: float | None = DEFAULT_TIMEOUT,
    binary: PathLike | None = None,
) -> xr.Dataset:
    """``rotorsweep simulate SCENE -o RUN.h5``: the run's runout as :func:`rotorsweep.runout`
    reads it (``vertical``, ``horizontal`` [um] over (sensor, time [s]); the run's status and
    solver statistics in ``attrs``). ``output`` keeps the file (for :func:`rotorsweep.spectrum`,
    :func:`rotorsweep.summary`, :func:`rotorsweep.orbits`, …). A run that did not end ok
    (exit code 2) is returned with a :class:`RotorsweepWarning`."""
    exe, args = _scene_args(scene, set, binary)
    with _Output(output, "simulate.h5") as out:
        p = _invoke(
            exe,
            ["simulate", *args, *_flags(overwrite=overwrite), "-o", str(out)],
            timeout=timeout,
            ok=(0, EXIT_NOT_OK),
        )
        _written(p, out)
        _warn_not_ok(p, "simulate")
        (job,) = results.job_ids(out)
        return results.runout(out, job)


def run(
    study: PathLike,
    *,
    output: PathLike | None = None,
    overwrite: bool = False,
    resume: bool = False,
    threads: int | None = None,
    shard: str | None = None,
    references_only: bool = False,
    references: PathLike | None = None,
    timeout: float | None = DEFAULT_TIMEOUT,
    binary: PathLike | None = None,
) -> pd.DataFrame:
    """``rotorsweep run STUDY -o OUT.h5``: the study's summary as :func:`rotorsweep.summary`
    reads it (one row per job, units in ``df.attrs["units"]``). ``output`` keeps the file (for
    :func:`rotorsweep.runout`, :func:`rotorsweep.spectral_map`, …; ``resume=True`` continues
    it). ``shard`` is "i/n". Jobs that did not end ok (exit code 2) are in the summary with
    their status, and a :class:`RotorsweepWarning` says so."""
    flags = _flags(
        threads=threads,
        resume=resume,
        overwrite=overwrite,
        shard=shard,
        references_only=references_only,
        references=str(references) if references is not None else None,
    )
    with _Output(output, "run.h5") as out:
        p = _invoke(
            _find_binary(binary),
            ["run", str(study), *flags, "-o", str(out)],
            timeout=timeout,
            ok=(0, EXIT_NOT_OK),
        )
        _written(p, out)
        _warn_not_ok(p, "run")
        return results.summary(out)
