"""The benchmark's tasks (protocol ``hapticsim-bench/2``): object family x sensing x backend x
touch budget, each with a fixed dev split and a fixed test split of episode seeds.

A task is named ``FAMILY/SENSING/BACKEND/tTOUCHES`` (``paper/exact/analytic/t20``):

- families: ``paper`` (the paper's four bodies), ``random`` (random tapered superquadrics),
  ``composite`` (unions of 2-4 superquadrics), ``holed`` (random rings: supertoroids, objects
  with a hole), ``pybullet`` (pybullet_data's procedural objects: meshes of a few fused convex
  blobs, 9-15 cm; extra ``objects``);
- sensing: ``exact`` (the simulator's contacts), ``vision`` and ``capacitive`` (contacts
  estimated from taxel pads with those skin presets);
- backends: ``analytic`` (ray casting on the exact surface) and ``mujoco`` (the hand);
- budgets: 20 and 50 touches.

Sensor noise is the environment's default (sigma_N = 0.02). Episode ``i`` of the dev split is
seeded ``DEV_SEED + i``, of the test split ``TEST_SEED + i`` (the same for every family, policy
and estimator, so results pair episode by episode); tune on dev, report test.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from hapticsim.errors import ChoiceError, InvalidInputError

#: The protocol's version: a change of tasks, splits or metrics is a new version (2: the
#: metrics from one fixed-sample scorer per episode, the ``pybullet`` family; 1 drew fresh
#: samples for every estimate).
PROTOCOL: str = "hapticsim-bench/2"
#: Object families and the environment's distribution each draws from.
FAMILIES: dict[str, str] = {"paper": "paper", "random": "random_tapered",
                            "composite": "random_composite", "holed": "random_holed",
                            "pybullet": "random_pybullet"}  # fmt: skip
#: Sensings: (the environment's sensing, skin preset).
SENSINGS: dict[str, tuple[str, str | None]] = {
    "exact": ("exact", None), "vision": ("tactile", "vision"),
    "capacitive": ("tactile", "capacitive"),
}  # fmt: skip
BACKENDS: tuple[str, ...] = ("analytic", "mujoco")
BUDGETS: tuple[int, ...] = (20, 50)
#: The splits' first seeds; each split holds :data:`SPLIT_SIZE` episodes.
DEV_SEED, TEST_SEED, SPLIT_SIZE = 0, 1_000_000, 1000
#: Relative sensor noise of every task (the environment's default).
NOISE: float = 0.02


@dataclass(frozen=True)
class Task:
    """One task of the protocol (module docstring)."""

    family: str
    sensing: str
    backend: str
    touches: int

    def __post_init__(self) -> None:
        if self.family not in FAMILIES:
            raise ChoiceError("family", self.family, FAMILIES)
        if self.sensing not in SENSINGS:
            raise ChoiceError("sensing", self.sensing, SENSINGS)
        if self.backend not in BACKENDS:
            raise ChoiceError("backend", self.backend, BACKENDS)
        if self.touches not in BUDGETS:
            raise ChoiceError("touches", self.touches, BUDGETS)

    @property
    def name(self) -> str:
        """``FAMILY/SENSING/BACKEND/tTOUCHES``."""
        return f"{self.family}/{self.sensing}/{self.backend}/t{self.touches}"

    def seeds(self, split: str, episodes: int) -> list[int]:
        """The first `episodes` seeds of the ``"dev"`` or ``"test"`` split."""
        if split not in ("dev", "test"):
            raise ChoiceError("split", split, ("dev", "test"))
        if not isinstance(episodes, int) or not 1 <= episodes <= SPLIT_SIZE:
            raise InvalidInputError(f"`episodes` must be in [1, {SPLIT_SIZE}], got {episodes!r}")
        first = DEV_SEED if split == "dev" else TEST_SEED
        return [first + i for i in range(episodes)]

    def env_kwargs(self) -> dict[str, Any]:
        """The settings of ``HapticExplore-v0`` (or its tactile core) for this task."""
        sensing, skin = SENSINGS[self.sensing]
        out: dict[str, Any] = {
            "backend": self.backend, "objects": FAMILIES[self.family],
            "touch_budget": self.touches, "noise": NOISE, "sensing": sensing,
        }  # fmt: skip
        if skin is not None:
            out["skin"] = skin
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the name, its parts and the environment's settings."""
        return {"name": self.name, "family": self.family, "sensing": self.sensing,
                "backend": self.backend, "touches": self.touches, "noise": NOISE,
                "env": self.env_kwargs()}  # fmt: skip


def task_names() -> list[str]:
    """Every task's name, in the protocol's order."""
    return [Task(f, s, b, t).name for f in FAMILIES for s in SENSINGS for b in BACKENDS
            for t in BUDGETS]  # fmt: skip


def get_task(name: str) -> Task:
    """The task of a name (:func:`task_names`).

    Raises:
        InvalidInputError: an unknown task (the nearest name suggested).
    """
    names = task_names()
    if not isinstance(name, str) or name not in names:
        import difflib

        close = difflib.get_close_matches(str(name), names, n=1, cutoff=0.6)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise InvalidInputError(
            f"unknown task {name!r}{hint}: `hapticsim bench tasks` lists the {len(names)} "
            "tasks, FAMILY/SENSING/BACKEND/tTOUCHES"
        )
    family, sensing, backend, touches = name.split("/")
    return Task(family, sensing, backend, int(touches[1:]))


__all__ = [
    "BACKENDS", "BUDGETS", "FAMILIES", "NOISE", "PROTOCOL", "SENSINGS", "Task", "get_task",
    "task_names",
]  # fmt: skip
