"""Suites as data: a TOML file names the suite, its kind, and the grids of cases it runs.

A suite file ``NAME-vVERSION.toml``::

    name = "fit"                 # the suite is "fit-v1"
    version = 1
    kind = "fit"                 # fit | explore | policy (hapticsim.suites.kinds)
    description = "..."
    seed = 0                     # root of every case's seed
    id = "{body}/{method}/noise={noise}/run={run}"   # a case's id (unique in the suite)
    group = "{body}/{method}"                         # cases pooled by `suite compare`

    [[grid]]                     # every combination of the listed values is a case
    body = ["cube", "cylinder"]
    method = ["LS", "nH"]
    noise = [0.0, 0.1]
    runs = 8                     # run = 0..7 (or list `run` explicitly)

A grid value is a scalar or a list; parameters left out take their defaults. A case's seeds are
keyed by its parameter values (never by its position), so a case keeps its data when cases are
added. The suites shipped with hapticsim live in ``hapticsim/suites/data``: adding ``fit-v2`` is
adding ``fit-v2.toml`` there. A suite file anywhere else can be run by its path.
"""

from __future__ import annotations

import hashlib
import itertools
import re
import string
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from fnmatch import fnmatchcase
from pathlib import Path
from typing import Any

from hapticsim._validate import did_you_mean
from hapticsim.errors import InvalidInputError
from hapticsim.suites.kinds import REQUIRED, Kind, get_kind

#: Where the shipped suite files live.
SUITES_DIR: Path = Path(__file__).resolve().parent / "data"
#: Keys of a suite file.
SUITE_KEYS: tuple[str, ...] = ("name", "version", "kind", "description", "seed", "id", "group")
_NAME = re.compile(r"[a-z][a-z0-9_]*")


@dataclass(frozen=True)
class Case:
    """One case of a suite: a kind, parameter values, an id and a group.

    Attributes:
        suite: the suite's id (``"fit-v1"``).
        kind: the kind (``"fit"``, ``"explore"``, ``"policy"``).
        id: unique in the suite, e.g. ``"cube/nH/noise=0.1/run=3"``.
        group: the group `suite compare` pools it in, e.g. ``"cube/nH"``.
        items: the parameter values as ``(name, value)`` pairs, in the kind's order.
        seed: the suite's root seed.
    """

    suite: str
    kind: str
    id: str
    group: str
    items: tuple[tuple[str, Any], ...]
    seed: int

    @property
    def params(self) -> dict[str, Any]:
        """The parameter values by name."""
        return dict(self.items)

    def data_params(self) -> dict[str, Any]:
        """The parameters that fix the case's data (see :class:`~hapticsim.suites.kinds.Param`)."""
        kind = get_kind(self.kind)
        return {p.name: v for p, (_, v) in zip(kind.params, self.items, strict=True) if p.data}


@dataclass(frozen=True)
class Suite:
    """A loaded suite.

    Attributes:
        name: e.g. ``"fit"``.
        version: e.g. 1.
        kind: the kind of all its cases.
        description: one paragraph.
        seed: root seed of its cases.
        cases: the cases, in file order (grids in order, combinations in parameter order).
        path: the file it was read from.
        sha256: SHA-256 of that file's bytes (recorded in results).
    """

    name: str
    version: int
    kind: str
    description: str
    seed: int
    cases: tuple[Case, ...]
    path: Path
    sha256: str

    @property
    def id(self) -> str:
        """``NAME-vVERSION``, e.g. ``"fit-v1"``."""
        return f"{self.name}-v{self.version}"

    @property
    def groups(self) -> tuple[str, ...]:
        """The group names, in order of first appearance."""
        return tuple(dict.fromkeys(c.group for c in self.cases))

    def select(self, pattern: str | None) -> tuple[Case, ...]:
        """The cases whose id matches the shell-style `pattern` (all cases when None).

        Raises:
            InvalidInputError: no case matches (the message shows a few ids).
        """
        if pattern is None:
            return self.cases
        chosen = tuple(c for c in self.cases if fnmatchcase(c.id, pattern))
        if not chosen:
            examples = ", ".join(c.id for c in self.cases[:3])
            raise InvalidInputError(
                f"--cases {pattern!r} matches no case of {self.id} (ids look like {examples})"
            )
        return chosen

    def summary(self) -> dict[str, Any]:
        """JSON-ready: id, name, version, kind, description, case and group counts, file."""
        return {
            "id": self.id, "name": self.name, "version": self.version, "kind": self.kind,
            "description": self.description, "cases": len(self.cases),
            "groups": len(self.groups), "file": str(self.path),
        }  # fmt: skip


def list_suites() -> list[Suite]:
    """The suites shipped with hapticsim, sorted by id.

    Raises:
        InvalidInputError: a shipped suite file is broken (a packaging bug, named).
    """
    return sorted((load_suite(p) for p in SUITES_DIR.glob("*.toml")), key=lambda s: s.id)


def suite_names() -> tuple[str, ...]:
    """Ids of the shipped suites (``fit-v1``, ...), sorted."""
    return tuple(sorted(p.stem for p in SUITES_DIR.glob("*.toml")))


def load_suite(name_or_path: str | Path) -> Suite:
    """A suite by id (``"fit-v1"``, shipped with hapticsim) or from a suite file's path.

    Raises:
        InvalidInputError: unknown suite (the message lists the shipped ones), unreadable or
            malformed file, unknown key, bad value, or two cases with one id.
    """
    if isinstance(name_or_path, str) and (SUITES_DIR / f"{name_or_path}.toml").is_file():
        path = SUITES_DIR / f"{name_or_path}.toml"
    else:
        path = Path(name_or_path)
        if path.suffix.lower() != ".toml" or not path.is_file():
            raise InvalidInputError(
                f"unknown suite {str(name_or_path)!r}{did_you_mean(name_or_path, suite_names())}: "
                "the suites are "
                f"{', '.join(suite_names())}, or give the path of a suite .toml file"
            )
    try:
        raw = path.read_bytes()
        data = tomllib.loads(raw.decode("utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InvalidInputError(f"cannot read suite file {path}: {exc}") from None
    return _parse(data, path, hashlib.sha256(raw).hexdigest())


def _parse(data: dict[str, Any], path: Path, sha256: str) -> Suite:
    where = f"suite file {path.name}"
    unknown = sorted(set(data) - set(SUITE_KEYS) - {"grid"})
    if unknown:
        raise InvalidInputError(
            f"{where}: unknown key(s) {unknown}; valid keys are {', '.join(SUITE_KEYS)}, grid"
        )
    missing = [k for k in SUITE_KEYS if k not in data]
    if missing:
        raise InvalidInputError(f"{where}: missing key(s) {missing}")
    name, version, seed = data["name"], data["version"], data["seed"]
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise InvalidInputError(
            f"{where}: `name` must be lower-case letters, digits, _; got {name!r}"
        )
    for key, value in (("version", version), ("seed", seed)):
        if isinstance(value, bool) or not isinstance(value, int) or value < (key == "version"):
            raise InvalidInputError(
                f"{where}: `{key}` must be an integer >= {int(key == 'version')}, got {value!r}"
            )
    if path.parent == SUITES_DIR and path.stem != f"{name}-v{version}":
        raise InvalidInputError(
            f"{where}: a shipped suite file must be named {name}-v{version}.toml"
        )
    kind = get_kind(data["kind"])
    suite_id = f"{name}-v{version}"
    templates = {k: data[k] for k in ("id", "group")}
    for key, template in templates.items():
        _check_template(template, kind, f"{where}: `{key}`")
    grids = data.get("grid")
    if not isinstance(grids, list) or not grids or not all(isinstance(g, dict) for g in grids):
        raise InvalidInputError(f"{where}: needs at least one [[grid]] table of cases")
    cases: list[Case] = []
    seen: dict[str, int] = {}
    for number, grid in enumerate(grids, start=1):
        for params in _expand(grid, kind, f"{where}, grid {number}"):
            case_id = templates["id"].format(**params)
            if case_id in seen:
                raise InvalidInputError(
                    f"{where}: two cases have the id {case_id!r} (grids {seen[case_id]} and "
                    f"{number}): put the parameter that tells them apart into `id`"
                )
            seen[case_id] = number
            cases.append(
                Case(
                    suite=suite_id,
                    kind=kind.name,
                    id=case_id,
                    group=templates["group"].format(**params),
                    items=tuple((n, params[n]) for n in kind.names),
                    seed=int(seed),
                )  # fmt: skip
            )
    if not isinstance(data["description"], str):
        raise InvalidInputError(f"{where}: `description` must be a string")
    return Suite(
        name=name, version=int(version), kind=kind.name, description=data["description"].strip(),
        seed=int(seed), cases=tuple(cases), path=path, sha256=sha256,
    )  # fmt: skip


def _check_template(template: Any, kind: Kind, where: str) -> None:
    if not isinstance(template, str) or not template:
        raise InvalidInputError(
            f'{where} must be a non-empty string such as "{{body}}/run={{run}}"'
        )
    try:
        fields = [f for _, f, _, _ in string.Formatter().parse(template) if f is not None]
    except ValueError as exc:
        raise InvalidInputError(f"{where} is not a valid template: {exc}") from None
    for field in fields:
        if field not in kind.names:
            raise InvalidInputError(
                f"{where} names {{{field}}}, which is not a parameter of {kind.name} cases "
                f"({', '.join(kind.names)})"
            )


def _expand(grid: Mapping[str, Any], kind: Kind, where: str) -> list[dict[str, Any]]:
    """The cases of one grid: every combination of its values, parameters in the kind's order."""
    grid = dict(grid)
    if "runs" in grid:
        if "run" in grid:
            raise InvalidInputError(f"{where}: give `runs` (a count) or `run` (a list), not both")
        runs = grid.pop("runs")
        if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
            raise InvalidInputError(f"{where}: `runs` must be an integer >= 1, got {runs!r}")
        grid["run"] = list(range(runs))
    for key in grid:
        try:
            kind.param(key)
        except InvalidInputError as exc:  # unknown key: named with the valid ones
            raise InvalidInputError(f"{where}: {exc}") from None
    axes: list[list[Any]] = []
    for param in kind.params:
        if param.name in grid:
            value = grid[param.name]
        elif param.default is REQUIRED:
            raise InvalidInputError(f"{where}: missing `{param.name}`")
        else:
            value = param.default
        values = value if isinstance(value, list) else [value]
        if not values:
            raise InvalidInputError(f"{where}: `{param.name}` is an empty list")
        try:
            checked = [param.check(v, param.name) for v in values]
        except InvalidInputError as exc:
            raise InvalidInputError(f"{where}: {exc}") from None
        if len(set(map(repr, checked))) != len(checked):
            raise InvalidInputError(f"{where}: `{param.name}` lists a value twice")
        axes.append(checked)
    return [dict(zip(kind.names, combo, strict=True)) for combo in itertools.product(*axes)]
