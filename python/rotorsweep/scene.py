"""A scene file in Python: read its keys, set them with ``--set`` semantics, save it.

>>> import rotorsweep as rs
>>> s = rs.Scene("studies/scenes/reference-roll.toml")
>>> s["roll.shell.outer_diameter_mm"]              # the effective value (after ``extends``)
320.0
>>> s.set("roll.shell.outer_diameter_mm", 300.0)    # checked by the binary, as ``--set`` is
>>> s.overrides
['roll.shell.outer_diameter_mm=300.0']
>>> rs.modes(s)                                    # runs the file with those ``--set`` arguments

In: a scene TOML file (it may ``extends`` another, relative to itself). Out: values as plain
Python (float, int, str, bool, list, dict), in the file's units (the key names say them: ``_mm``,
``_hz``, ``_kg``).

Keys are the dotted keys of ``rotorsweep --set`` (docs/scenes.md): tables by name, arrays by
``[i]`` (``supports[0].stand.mass_kg``, ``roll.sensors[1].z_mm``). A key is read from the
*effective* scene: the file merged over what it ``extends`` (tables key by key, any other value
replaced whole; ``wall_thickness_mm``, ``thickness_map`` and ``synthetic_map`` exclude each other,
and so do ``[roll]`` and ``[rotor]``), as the binary merges it.

:meth:`Scene.set` is ``--set KEY=VALUE``: the path is walked in the effective scene, creating
tables on the way (a path through a value that is no table, or an index past an array's end, is
a :class:`SceneKeyError`); then, when a binary is found, ``rotorsweep check SCENE --no-model``
with every override so far validates the result as a run would (an unknown key is a
:class:`SceneKeyError`, a wrong type or a value out of range a :class:`SceneValueError`, each with
the binary's message, which names the key) and a refused value is not kept. A key that replaces
an earlier one (``speed.hz`` after ``speed.hz.x``) is refused, as on the command line.

The runners (:func:`rotorsweep.modes`, …) pass a :class:`Scene` to the binary as its file with
the overrides as ``--set`` arguments: the file on disk is not touched, and ``extends`` and the
thickness map stay relative to it. :meth:`Scene.save` writes the file with the set values in
place (comments and layout kept, through tomlkit); saved in another folder, its relative
``extends`` and ``roll.shell.thickness_map`` are rewritten to name the same files.
"""

from __future__ import annotations

import copy
import math
import os
import re
import tomllib
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any, Union

import tomlkit
import tomlkit.items

from .runner import RotorsweepError, _find_binary, _invoke

PathLike = Union[str, "os.PathLike[str]"]

#: Keys whose values are paths relative to the file that writes them (besides ``extends``).
PATH_KEYS = ("roll.shell.thickness_map",)
#: Keys that exclude each other, by the table that holds them: giving one drops the others.
EXCLUSIVE = (("", ("roll", "rotor")), ("roll.shell", ("wall_thickness_mm", "thickness_map", "synthetic_map")))
#: Most files in one chain of ``extends`` (the binary's limit).
MAX_EXTENDS_DEPTH = 16


class SceneError(RotorsweepError, ValueError):
    """A scene value the binary refuses (also a :class:`ValueError`); ``key`` is the dotted key."""

    def __init__(self, message: str, key: str, returncode: int | None = None, stderr: str = "") -> None:
        super().__init__(message, returncode=returncode, stderr=stderr)
        self.key = key


class SceneKeyError(SceneError, KeyError):
    """A key the scene has not, or a path that does not fit its structure (also a
    :class:`KeyError`)."""

    def __str__(self) -> str:  # KeyError would quote the message
        return self.message


class SceneValueError(SceneError, TypeError):
    """A value of the wrong type or out of range for its key (a :class:`ValueError` and a
    :class:`TypeError`)."""


# --- dotted keys -----------------------------------------------------------------------------


def parse_key(key: str) -> list[str | int]:
    """The steps of a dotted key with ``[i]`` indices, as the binary splits it:
    ``"supports[0].stand.mass_kg"`` → ``["supports", 0, "stand", "mass_kg"]``."""
    steps: list[str | int] = []
    for part in key.split("."):
        i = part.find("[")
        if i < 0:
            if part:
                steps.append(part)
            continue
        if i > 0:
            steps.append(part[:i])
        rest = part[i:]
        while rest.startswith("["):
            end = rest.find("]")
            inner = rest[1:end] if end >= 0 else rest[1:]
            if inner.isdigit():
                steps.append(int(inner))
            rest = rest[end + 1 :] if end >= 0 else ""
    return steps


def _plain(v: Any) -> Any:
    """A tomlkit item (or container) as plain Python values."""
    if hasattr(v, "unwrap"):
        return v.unwrap()
    return v


def toml_value(value: Any) -> str:
    """``value`` as one TOML value (what ``--set KEY=VALUE`` parses): numbers, strings, booleans,
    lists and dicts (inline tables); numpy scalars as Python's."""
    if hasattr(value, "item") and not isinstance(value, (list, tuple, dict)) and getattr(value, "shape", None) == ():
        value = value.item()
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, Mapping):
        inner = ", ".join(f"{_toml_key(str(k))} = {toml_value(v)}" for k, v in value.items())
        return "{ " + inner + " }" if inner else "{}"
    if isinstance(value, (list, tuple)) or (hasattr(value, "tolist") and hasattr(value, "shape")):
        items = value.tolist() if hasattr(value, "tolist") else value
        return "[" + ", ".join(toml_value(v) for v in items) + "]"
    raise TypeError(f"no TOML value for {type(value).__name__} {value!r}")


def _toml_string(s: str) -> str:
    escapes = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t", "\r": "\\r", "\b": "\\b", "\f": "\\f"}
    out = []
    for ch in s:
        if ch in escapes:
            out.append(escapes[ch])
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else _toml_string(k)


# --- extends: the effective table --------------------------------------------------------------


def _merge(base: dict[str, Any], child: Mapping[str, Any], at: str = "") -> None:
    """Merges ``child`` over ``base`` in place (module doc: the binary's rules)."""
    for table, group in EXCLUSIVE:
        if table == at and any(k in child for k in group):
            for k in [k for k in base if k in group and k not in child]:
                del base[k]
    for k, v in child.items():
        if isinstance(base.get(k), dict) and isinstance(v, Mapping):
            _merge(base[k], v, f"{at}.{k}" if at else k)
        else:
            base[k] = copy.deepcopy(v)


def _at(table: Mapping[str, Any], dotted: str) -> Any:
    node: Any = table
    for k in dotted.split("."):
        if not isinstance(node, Mapping) or k not in node:
            return None
        node = node[k]
    return node


def _load_chain(path: Path, seen: list[Path]) -> dict[str, Any]:
    """The merged table of ``path`` and the files it extends, ``extends`` removed; the paths of
    :data:`PATH_KEYS` of a base made relative to the extending file (as the binary does)."""
    real = path.resolve()
    if real in seen:
        chain = " → ".join(str(p) for p in [*seen, real])
        raise SceneError(f"{path}: a cycle of extends: {chain}", key="extends")
    if len(seen) >= MAX_EXTENDS_DEPTH:
        raise SceneError(f"{path}: a chain of more than {MAX_EXTENDS_DEPTH} scene files", key="extends")
    try:
        table = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise SceneError(f"{path}: {e}", key="") from e
    base = table.pop("extends", None)
    if base is None:
        return table
    merged = _base_table(path, base, [*seen, real])
    _merge(merged, table)
    return merged


def _base_table(path: Path, base: Any, seen: list[Path]) -> dict[str, Any]:
    """The merged table of the scene ``path`` extends (``base``, relative to it), its
    :data:`PATH_KEYS` made relative to ``path``'s folder."""
    if not isinstance(base, str) or not base.strip():
        raise SceneKeyError(f"{path}: key `extends`: must be the path of a scene file (relative to this file), got {base!r}", key="extends")
    merged = _load_chain(path.parent / base, seen)
    rel = Path(base).parent
    for key in PATH_KEYS:
        parent, _, leaf = key.rpartition(".")
        holder = _at(merged, parent)
        if isinstance(holder, dict) and isinstance(holder.get(leaf), str) and not Path(holder[leaf]).is_absolute():
            holder[leaf] = (rel / holder[leaf]).as_posix()
    return merged


# --- the Scene ---------------------------------------------------------------------------------

_MISSING = object()


class Scene:
    """A scene file: key access on the effective scene, ``set`` with ``--set`` semantics,
    ``save`` keeping comments and layout (module doc).

    ``scene["speed.hz"]``, ``scene.get("speed.hz", default)``, ``"speed.hz" in scene``,
    ``scene["speed.hz"] = 14.0`` (= ``set``); ``scene.overrides`` are the ``--set`` arguments
    so far, ``scene.path`` the file (absolute), ``scene.text`` the file as :meth:`save` writes
    it. ``binary`` names the rotorsweep binary that validates :meth:`set` and that the runners
    use for this scene (default: found as the runners find it; with ``check=False`` there, or
    no binary found, values are not validated until a run).
    """

    def __init__(self, path: PathLike, *, binary: PathLike | None = None) -> None:
        self.path = Path(path).absolute()
        try:
            text = self.path.read_text(encoding="utf-8")
        except OSError as e:
            raise SceneError(f"{path}: cannot read the scene file: {e.strerror or e}", key="") from e
        try:
            self._doc = tomlkit.parse(text)
        except tomlkit.exceptions.ParseError as e:
            raise SceneError(f"{path}: {e}", key="") from e
        base = self._doc.get("extends")
        self._base = _base_table(self.path, _plain(base), [self.path.resolve()]) if base is not None else {}
        self.binary = binary
        self._overrides: list[tuple[str, str]] = []

    def __repr__(self) -> str:
        sets = f", {len(self._overrides)} override(s)" if self._overrides else ""
        return f"Scene({str(self.path)!r}{sets})"

    # -- reading --

    def effective(self) -> dict[str, Any]:
        """The effective scene as a dict: the file (with the values set) merged over its bases."""
        merged = copy.deepcopy(self._base)
        own = _plain(self._doc)
        own.pop("extends", None)
        _merge(merged, own)
        return merged

    def _lookup(self, key: str) -> Any:
        node: Any = self.effective()
        steps = parse_key(key)
        if not steps:
            raise SceneKeyError(f"{self.path}: empty key", key=key)
        for n, step in enumerate(steps):
            where = _describe(steps[:n])
            if isinstance(step, int):
                if not isinstance(node, list):
                    raise SceneKeyError(f"{self.path}: key `{key}`: {where} is no array", key=key)
                if step >= len(node):
                    raise SceneKeyError(
                        f"{self.path}: key `{key}`: index {step} out of range (length {len(node)})", key=key
                    )
            elif not isinstance(node, dict) or step not in node:
                raise SceneKeyError(f"{self.path}: no key `{key}` in the scene{_no_key_hint(node, step)}", key=key)
            node = node[step]
        return node

    def __getitem__(self, key: str) -> Any:
        return self._lookup(key)

    def get(self, key: str, default: Any = None) -> Any:
        """The value of ``key``, or ``default`` where the scene has none."""
        try:
            return self._lookup(key)
        except SceneKeyError:
            return default

    def __contains__(self, key: object) -> bool:
        return isinstance(key, str) and self.get(key, _MISSING) is not _MISSING

    def keys(self) -> Iterator[str]:
        """Every leaf key of the effective scene, dotted (arrays as ``[i]``)."""
        yield from _leaves(self.effective(), "")

    @property
    def name(self) -> str:
        """The scene's ``name``."""
        return str(self.get("name", self.path.stem))

    @property
    def overrides(self) -> list[str]:
        """The values set, as ``--set`` arguments ``KEY=VALUE`` (TOML values), in order."""
        return [f"{k}={v}" for k, v in self._overrides]

    # -- setting --

    def set(self, key: str, value: Any, *, check: bool = True) -> Scene:
        """Sets ``key`` to ``value`` as ``--set KEY=VALUE`` would (module doc); returns the scene.

        ``value`` is a Python value (number, str, bool, list, dict) and is written as TOML; a
        str is a TOML string (``"0.25L"``), never parsed. With ``check`` (the default) the
        binary validates the scene with every override so far (``rotorsweep check --no-model``)
        and a refused value raises :class:`SceneKeyError` or :class:`SceneValueError` with its
        message and is not kept."""
        return self.update({key: value}, check=check)

    def update(self, values: Mapping[str, Any], *, check: bool = True) -> Scene:
        """Sets several keys (in order), validated once at the end: values that are only valid
        together (a smaller shell and a balancing radius inside it) are set in one call. If
        one is refused, none is kept."""
        doc, overrides = copy.deepcopy(self._doc), list(self._overrides)
        try:
            for key, value in values.items():
                self._set_one(key, value)
            if check:
                self.check()
        except BaseException:
            self._doc, self._overrides = doc, overrides
            raise
        return self

    def _set_one(self, key: str, value: Any) -> None:
        steps = parse_key(key)
        if not steps:
            raise SceneKeyError(f"{self.path}: empty key", key=key)
        text = toml_value(value)
        plain = tomllib.loads(f"v = {text}")["v"]
        for earlier, _ in self._overrides:
            if _replaces(key, earlier):
                raise SceneKeyError(
                    f"<command line --set>: `{key}` would replace `{earlier}`, given before it: "
                    f"`{earlier}` would be dropped",
                    key=key,
                )
        _set_path(self.effective(), steps, plain, key)  # the path must fit the effective scene
        self._set_in_doc(steps, plain)
        self._overrides = [(k, v) for k, v in self._overrides if k != key] + [(key, text)]

    def check(self, *, timeout: float | None = 120.0) -> None:
        """Validates the scene with its overrides by ``rotorsweep check SCENE --no-model --set
        …`` (read and check every value, build no model); a refusal is a
        :class:`SceneKeyError` (an unknown key, a path that does not fit) or a
        :class:`SceneValueError` (wrong type, out of range, inconsistent), with the binary's
        message, which names the key. Does nothing when no binary is found."""
        try:
            binary = _find_binary(self.binary)
        except RotorsweepError:
            return
        args = ["check", str(self.path), "--no-model"]
        for k, v in self._overrides:
            args += ["--set", f"{k}={v}"]
        try:
            _invoke(binary, args, timeout=timeout)
        except RotorsweepError as e:
            if e.returncode != 1:
                raise
            m = re.search(r"key `([^`]+)`", e.message)
            key = m.group(1) if m else (self._overrides[-1][0] if self._overrides else "")
            unknown = re.search(
                r"unknown (field|key)|does not match the file's structure|out of range \(length|would replace",
                e.message,
            )
            cls = SceneKeyError if unknown else SceneValueError
            raise cls(e.message, key=key, returncode=e.returncode, stderr=e.stderr) from None

    def __setitem__(self, key: str, value: Any) -> None:
        self.set(key, value)

    def _set_in_doc(self, steps: list[str | int], value: Any) -> None:
        """Writes ``value`` at ``steps`` into the file's own document: tables the file lacks are
        created; an array the file does not write (its base's) is first copied in whole, since
        the file's array would replace the base's."""
        node: Any = self._doc
        eff: Any = self.effective()
        sections = True  # new tables here are [sections], not inline
        for step in steps[:-1]:
            eff = eff[step] if _has(eff, step) else {}
            if isinstance(step, str) and step not in node:
                node[step] = _item(eff if isinstance(eff, list) else {}, inline=not sections)
            node = node[step]
            sections = sections and isinstance(step, str) and isinstance(node, tomlkit.items.Table)
        node[steps[-1]] = _item(value, inline=not sections)

    # -- writing --

    @property
    def text(self) -> str:
        """The file as :meth:`save` writes it in its own folder."""
        return tomlkit.dumps(self._doc)

    def save(self, path: PathLike | None = None, *, overwrite: bool = False) -> Path:
        """Writes the scene with the values set to ``path`` (default: over its own file, which
        needs ``overwrite=True``); comments and layout are kept. In another folder, the relative
        ``extends`` and ``roll.shell.thickness_map`` are rewritten to name the same files.
        Returns the path written; an existing file is replaced only with ``overwrite``."""
        target = Path(path).absolute() if path is not None else self.path
        if target.exists() and not overwrite:
            raise FileExistsError(f"{target} exists: pass overwrite=True to replace it")
        doc = copy.deepcopy(self._doc)
        if target.parent.resolve() != self.path.parent.resolve():
            for key in ("extends", *PATH_KEYS):
                *parents, leaf = key.split(".")
                holder: Any = doc
                for p in parents:
                    holder = holder.get(p) if hasattr(holder, "get") else None
                value = holder.get(leaf) if hasattr(holder, "get") else None
                if isinstance(value, str) and not Path(value).is_absolute():
                    holder[leaf] = _relative(self.path.parent / str(value), target.parent)
        tmp = target.with_name(target.name + ".tmp")
        tmp.write_text(tomlkit.dumps(doc), encoding="utf-8")
        os.replace(tmp, target)
        return target


def _relative(file: Path, folder: Path) -> str:
    """``file`` relative to ``folder`` (POSIX separators), or absolute where it cannot be."""
    try:
        return Path(os.path.relpath(file, folder)).as_posix()
    except ValueError:  # another drive
        return file.resolve().as_posix()


def _has(node: Any, step: str | int) -> bool:
    if isinstance(step, int):
        return isinstance(node, list) and step < len(node)
    return isinstance(node, dict) and step in node


def _item(value: Any, *, inline: bool) -> Any:
    """``value`` as a tomlkit item: dicts as tables (inline below an array or inline table),
    lists of dicts as ``[[arrays of tables]]`` whose elements hold their own tables inline."""
    if inline:
        return tomlkit.parse(f"v = {toml_value(value)}")["v"]
    if isinstance(value, Mapping):
        t = tomlkit.table()
        for k, v in value.items():
            t[k] = _item(v, inline=True)
        return t
    if isinstance(value, list) and value and all(isinstance(v, Mapping) for v in value):
        aot = tomlkit.aot()
        for v in value:
            aot.append(_item(v, inline=False))
        return aot
    return _item(value, inline=True)


def _set_path(root: dict[str, Any], steps: list[str | int], value: Any, key: str) -> None:
    """``--set``'s walk (the binary's ``set_path``): tables created on the way, arrays indexed
    in range; anything else does not fit the scene's structure."""
    node: Any = root
    for n, step in enumerate(steps):
        last = n + 1 == len(steps)
        if isinstance(step, str) and isinstance(node, dict):
            if last:
                node[step] = value
                return
            node = node.setdefault(step, {})
        elif isinstance(step, int) and isinstance(node, list):
            if step >= len(node):
                raise SceneKeyError(f"<command line --set>: `{key}`: index {step} out of range (length {len(node)})", key=key)
            if last:
                node[step] = value
                return
            node = node[step]
        elif isinstance(step, str) and isinstance(node, list):
            hint = (
                f"; arrays are indexed with brackets: write `…[{step}]…` (e.g. `supports[0].stand.mass_kg`)"
                if step.isdigit()
                else f" (an array of {len(node)} entries: index it as `[i]`)"
            )
            raise SceneKeyError(f"<command line --set>: `{key}`: the path does not match the file's structure{hint}", key=key)
        else:
            raise SceneKeyError(f"<command line --set>: `{key}`: the path does not match the file's structure", key=key)


def _replaces(later: str, earlier: str) -> bool:
    """Whether ``later`` replaces ``earlier`` (lies strictly above it: ``speed.hz`` after
    ``speed.hz.x``)."""
    lt, et = parse_key(later), parse_key(earlier)
    return len(lt) < len(et) and et[: len(lt)] == lt


def _describe(steps: list[str | int]) -> str:
    out = ""
    for s in steps:
        out += f"[{s}]" if isinstance(s, int) else (f".{s}" if out else s)
    return f"`{out}`" if out else "the scene"


def _no_key_hint(node: Any, step: str | int) -> str:
    if isinstance(node, dict) and node:
        return f" (there: {', '.join(map(str, node))})"
    return ""


def _leaves(node: Any, prefix: str) -> Iterator[str]:
    if isinstance(node, dict) and node:
        for k, v in node.items():
            yield from _leaves(v, f"{prefix}.{k}" if prefix else k)
    elif isinstance(node, list) and node and all(isinstance(v, dict) for v in node):
        for i, v in enumerate(node):
            yield from _leaves(v, f"{prefix}[{i}]")
    else:
        yield prefix
