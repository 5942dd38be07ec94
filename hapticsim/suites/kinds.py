"""The three kinds of suite cases and their parameters: ``fit``, ``explore``, ``policy``.

A kind lists the parameters a case of that kind has (with defaults and checks), which of them
fix the *data* (the contacts, the exploration, the episode's object and noise: cases that differ
only in the method or the policy see the same data, so they pair), and which parameter a user's
plug-in replaces (``--fitter`` replaces ``method``, ``--policy`` replaces ``policy``).

Valid choices come from the code's registries when a suite is loaded (``fitting.METHODS``, the
exploration strategies, ``envs.policies.POLICY_NAMES``, ...), so a method, strategy or policy
added there can be named in a suite file at once.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from hapticsim.data.bodies import BODY_NAMES
from hapticsim.errors import ChoiceError, InvalidInputError

#: Marks a parameter without default.
REQUIRED: Any = object()
#: Random bodies of ``fit`` suites (drawn per run from the data seed).
RANDOM_BODIES: tuple[str, ...] = ("random", "random_tapered")
#: Contact patterns of ``fit`` suites.
PATTERNS: tuple[str, ...] = ("paper",)


def _choice(choices: Callable[[], Sequence[str]]) -> Callable[[Any, str], str]:
    def check(value: Any, name: str) -> str:
        valid = tuple(choices())
        if not isinstance(value, str) or value not in valid:
            raise ChoiceError(name, value, valid)
        return value

    return check


def _integer(low: int) -> Callable[[Any, str], int]:
    def check(value: Any, name: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            raise InvalidInputError(f"`{name}` must be an integer >= {low}, got {value!r}")
        return int(value)

    return check


def _fraction(value: Any, name: str) -> float:
    ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    if not ok or not np.isfinite(value) or not 0.0 <= value <= 1.0:
        raise InvalidInputError(f"`{name}` must be a number in [0, 1], got {value!r}")
    return float(value)


def _budget(value: Any, name: str) -> int | str:
    if value == "default":
        return "default"
    if isinstance(value, bool) or not isinstance(value, int) or value < 2:
        raise InvalidInputError(
            f'`{name}` must be an integer >= 2 or "default" (the fitter\'s default budget), '
            f"got {value!r}"
        )
    return int(value)


def _bodies() -> tuple[str, ...]:
    return (*BODY_NAMES, *RANDOM_BODIES)


def _paper_bodies() -> tuple[str, ...]:
    return tuple(BODY_NAMES)


def _methods() -> tuple[str, ...]:
    from hapticsim.fitting import FIT_METHODS

    return tuple(FIT_METHODS)


def _strategies() -> tuple[str, ...]:
    from hapticsim.sim.strategies import strategy_names

    return strategy_names()


def _explorations() -> tuple[str, ...]:
    from hapticsim.exploration import explorer_names

    return explorer_names()


def _object(value: Any, name: str) -> str:
    """An object of ``objects`` cases: a paper body, a random kind (drawn from the data seed),
    an example mesh (:data:`hapticsim.data.example_meshes.EXAMPLE_MESHES`) or ``pybullet:NAME``
    (checked when a case runs: the extra may be missing where the suite is only listed)."""
    from hapticsim.data.example_meshes import EXAMPLE_MESHES
    from hapticsim.data.objects import ObjectSpec

    if isinstance(value, str) and (value in EXAMPLE_MESHES or value.startswith("pybullet:")):
        return value
    if isinstance(value, str):
        try:
            spec = ObjectSpec(value)
        except InvalidInputError:
            spec = None
        if spec is not None and spec.kind in ("body", "random", "random_tapered",
                                              "random_composite", "random_holed",
                                              "random_handled"):  # fmt: skip
            return value
    raise InvalidInputError(
        f"`{name}` must be a paper body, random, random_tapered, random_composite, "
        f"random_holed, random_handled, an example "
        f"mesh ({', '.join(EXAMPLE_MESHES)}) or pybullet:NAME, got {value!r}"
    )


def _policies() -> tuple[str, ...]:
    from hapticsim.envs.policies import POLICY_NAMES

    return tuple(POLICY_NAMES)


def _object_kinds() -> tuple[str, ...]:
    from hapticsim.data.distributions import OBJECT_KINDS

    return tuple(OBJECT_KINDS)


def _backends() -> tuple[str, ...]:
    from hapticsim.envs.backends import BACKENDS

    return tuple(BACKENDS)


@dataclass(frozen=True)
class Param:
    """One parameter of a case.

    Attributes:
        name: its name in suite files and in results.
        check: ``check(value, name) -> value``, raising InvalidInputError for a bad value.
        default: the value when a grid leaves it out; :data:`REQUIRED` if it must be given.
        data: whether it fixes the case's data (its seed key): cases equal in every data
            parameter see the same contacts, exploration or episode.
        doc: one line for the docs.
    """

    name: str
    check: Callable[[Any, str], Any]
    default: Any = REQUIRED
    data: bool = True
    doc: str = ""


@dataclass(frozen=True)
class Kind:
    """A kind of case: its parameters and the one a plug-in replaces.

    Attributes:
        name: ``"fit"``, ``"explore"`` or ``"policy"``.
        params: the parameters, in the order cases are enumerated.
        plugin: the plug-in option that applies (``"fitter"`` or ``"policy"``).
        replaces: the parameter that plug-in takes the place of.
        description: one sentence.
    """

    name: str
    params: tuple[Param, ...]
    plugin: str
    replaces: str
    description: str

    def param(self, name: str) -> Param:
        """The parameter called `name`.

        Raises:
            InvalidInputError: no such parameter (the message lists them).
        """
        for p in self.params:
            if p.name == name:
                return p
        names = ", ".join(p.name for p in self.params)
        raise InvalidInputError(
            f"`{name}` is not a parameter of {self.name} cases; they have {names} (and `runs`)"
        )

    @property
    def names(self) -> tuple[str, ...]:
        """Parameter names in order."""
        return tuple(p.name for p in self.params)


_RUN = Param("run", _integer(0), doc="repetition index (a fresh data set per run)")

KINDS = MappingProxyType(
    {
        "fit": Kind(
            "fit",
            (
                Param("body", _choice(_bodies), doc="a paper body, or random/random_tapered"),
                Param("method", _choice(_methods), data=False, doc="fitting method"),
                Param("noise", _fraction, doc="relative noise sigma_N (SPEC §5)"),
                Param("count", _integer(13), 150, doc="contacts"),
                Param("pattern", _choice(lambda: PATTERNS), "paper", doc="contact pattern"),
                Param("budget", _budget, "default", data=False, doc="EOF evaluations"),
                _RUN,
            ),
            plugin="fitter",
            replaces="method",
            description="synthetic contact sets (paper III-A), fitted and scored",
        ),
        "explore": Kind(
            "explore",
            (
                Param("body", _choice(_paper_bodies), doc="a paper body"),
                Param("strategy", _choice(_strategies), doc="exploration strategy of the hand"),
                Param("noise", _fraction, doc="sensor noise sigma_N (SPEC §5)"),
                Param("method", _choice(_methods), "nH", data=False, doc="fitting method"),
                Param("count", _integer(20), 150, doc="contacts to gather"),
                _RUN,
            ),
            plugin="fitter",
            replaces="method",
            description="simulated hand explorations (MuJoCo), fitted and scored",
        ),
        "objects": Kind(
            "objects",
            (
                Param("object", _object, doc="a body, random kind, example mesh or pybullet:NAME"),
                Param("strategy", _choice(_explorations), doc="a strategy or environment policy"),
                Param("noise", _fraction, 0.0, doc="sensor noise sigma_N (SPEC §5)"),
                Param("method", _choice(_methods), "nH", data=False, doc="fitting method"),
                Param("count", _integer(20), 150, doc="contacts to gather"),
                _RUN,
            ),
            plugin="fitter",
            replaces="method",
            description="hand explorations of any object (composites, meshes), fitted and scored",
        ),
        "policy": Kind(
            "policy",
            (
                Param("policy", _choice(_policies), data=False, doc="exploration policy"),
                Param("objects", _choice(_object_kinds), doc="object distribution"),
                Param("backend", _choice(_backends), doc="touch backend of the environment"),
                Param("touches", _integer(1), 10, data=False, doc="touches per episode"),
                Param("noise", _fraction, 0.02, doc="sensor noise sigma_N"),
                _RUN,
            ),
            plugin="policy",
            replaces="policy",
            description="episodes of HapticExplore-v0, scored after the last touch",
        ),
    }
)


def get_kind(name: Any) -> Kind:
    """The kind called `name`.

    Raises:
        InvalidInputError: an unknown kind (the message lists the kinds).
    """
    if not isinstance(name, str) or name not in KINDS:
        raise ChoiceError("kind", name, KINDS)
    return KINDS[name]
