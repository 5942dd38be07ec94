"""The strategies: ``patch``, ``stripe``, ``sweep`` and ``paper`` (registered on import).

- ``patch``: single-finger probing of randomised patches spread over the object (index and
  thumb in turn), paper III-A "patch".
- ``stripe``: single-finger contour following (middle finger) across edges of the object,
  paper III-A "stripe"; on a round body the stripes cross its curvature instead.
- ``sweep``: three fingers follow parallel contours across an edge while the thumb probes the
  corner at the end of that edge (paper IV), repeated over several edges.
- ``paper``: the paper's composition. Prismatic bodies: a corner patch covering the adjacent
  faces (index finger), then three-finger sweeps with the thumb on a corner across three edges
  chosen so that every face of the body is touched; round bodies: patches only, probed with
  thumb and index. Fill-in patches make up any shortfall.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from hapticsim.sim.explorer import Explorer
from hapticsim.sim.strategies.geometry import corner_probes, patch_probes
from hapticsim.sim.strategies.registry import register
from hapticsim.sim.strategies.sweep import plan_sweep, run_sweep_plan

#: Edges (face A, face B) of a box swept by the ``paper`` strategy: top-front, bottom-back and
#: back-right; together with the top-front-left corner patch they touch all six faces.
PAPER_EDGES: tuple[tuple[tuple[int, float], tuple[int, float]], ...] = (
    ((0, 1.0), (2, 1.0)),
    ((0, -1.0), (2, -1.0)),
    ((1, -1.0), (0, -1.0)),
)
#: Further edges for the ``stripe`` and ``sweep`` strategies.
MORE_EDGES: tuple[tuple[tuple[int, float], tuple[int, float]], ...] = (
    ((1, 1.0), (2, 1.0)),
    ((1, -1.0), (2, -1.0)),
    ((0, 1.0), (1, 1.0)),
)
#: Corner of the ``paper`` corner patch (body-axis signs).
PAPER_CORNER: tuple[float, float, float] = (1.0, 1.0, 1.0)
#: Patch centres (eta, omega) [rad] for round bodies: top, four sides, lower side.
ROUND_PATCHES: tuple[tuple[float, float], ...] = (
    (1.15, 0.0),
    (0.0, 0.0),
    (0.1, 0.5 * np.pi),
    (0.0, np.pi),
    (0.1, -0.5 * np.pi),
    (-0.6, 0.25 * np.pi),
)
#: Half-width of a patch in eta and omega [rad].
PATCH_HALF_WIDTH: float = np.radians(22.0)
#: Thumb probes per sweep.
THUMB_PROBES: int = 8


def _fill(explorer: Explorer, count: int, rng: np.random.Generator, rounds: int = 12) -> None:
    """Random patches (index finger and thumb in turn) until the recorder is full or `rounds`
    patches ran. The missing contacts are shared out over the rounds left (plus two probes for
    misses), so that a fill spreads over the object instead of piling into one patch."""
    hand = explorer.scene.hand
    for k in range(rounds):
        missing = count - len(explorer.recorder)
        if missing <= 0 or explorer.out_of_time:
            return
        eta0 = rng.uniform(-0.6, 1.1)
        omega0 = rng.uniform(-np.pi, np.pi)
        share = int(np.ceil(missing / (rounds - k))) + 2
        probes = patch_probes(
            explorer.rough, (eta0 - PATCH_HALF_WIDTH, eta0 + PATCH_HALF_WIDTH),
            (omega0 - PATCH_HALF_WIDTH, omega0 + PATCH_HALF_WIDTH), share, rng,
        )  # fmt: skip
        explorer.probe_patch(hand.index if k % 2 == 0 else hand.thumb, probes)


def _patches(
    explorer: Explorer, count: int, rng: np.random.Generator,
    centres: tuple[tuple[float, float], ...], fingers: tuple[int, ...] | None = None,
) -> None:  # fmt: skip
    """Patches at `centres`, probed in turn by `fingers` (default: index and thumb)."""
    if fingers is None:
        fingers = (explorer.scene.hand.index, explorer.scene.hand.thumb)
    per = int(np.ceil(count / len(centres)))
    for k, (eta0, omega0) in enumerate(centres):
        if explorer.recorder.full or explorer.out_of_time:
            return
        n = min(per, count - len(explorer.recorder))
        probes = patch_probes(
            explorer.rough, (eta0 - PATCH_HALF_WIDTH, eta0 + PATCH_HALF_WIDTH),
            (omega0 - PATCH_HALF_WIDTH, omega0 + PATCH_HALF_WIDTH), n, rng,
        )  # fmt: skip
        explorer.probe_patch(fingers[k % len(fingers)], probes)


def _sweeps(
    explorer: Explorer,
    count: int,
    rng: np.random.Generator,
    edges: tuple[tuple[tuple[int, float], tuple[int, float]], ...],
    fingers: tuple[int, ...] | None,
    thumb_probes: int,
) -> None:
    """Plan all sweeps, choose the stripe spacing that fills the budget, run them (`fingers`
    None: the hand's sweeping fingers)."""
    plans = [(e, plan_sweep(explorer, e[0], e[1], fingers)) for e in edges]
    plans = [(e, p) for e, p in plans if p is not None]
    if not plans:
        return
    missing = count - len(explorer.recorder)
    stripe_contacts = missing - thumb_probes * len(plans)
    n_stripes = sum(len(p.stripes) for _, p in plans)
    total = sum(p.total_length for _, p in plans)
    spacing = float(np.clip(total / max(stripe_contacts - n_stripes, 1), 0.0025, 0.012))
    cfg = explorer.config
    explorer.config = replace(cfg, follow=replace(cfg.follow, spacing=spacing))
    try:
        for edge, plan in plans:
            if explorer.recorder.full or explorer.out_of_time:
                return
            run_sweep_plan(explorer, plan, edge[0], edge[1], thumb_probes, rng)
    finally:
        explorer.config = cfg


@register("patch")
def patch_strategy(explorer: Explorer, count: int, rng: np.random.Generator) -> None:
    """Randomised probing patches over the object (index and thumb in turn)."""
    _patches(explorer, count, rng, ROUND_PATCHES)
    _fill(explorer, count, rng)


@register("stripe")
def stripe_strategy(explorer: Explorer, count: int, rng: np.random.Generator) -> None:
    """Single-finger contour following across edges (the hand's middle sweeping finger)."""
    middle = (explorer.scene.hand.middle,)
    _sweeps(explorer, count, rng, PAPER_EDGES + MORE_EDGES, fingers=middle, thumb_probes=0)
    _fill(explorer, count, rng)


@register("sweep")
def sweep_strategy(explorer: Explorer, count: int, rng: np.random.Generator) -> None:
    """Three fingers sweep across edges while the thumb probes a corner."""
    _sweeps(explorer, count, rng, PAPER_EDGES + MORE_EDGES[:1], None, THUMB_PROBES)
    _fill(explorer, count, rng)


@register("paper")
def paper_strategy(explorer: Explorer, count: int, rng: np.random.Generator) -> None:
    """The paper's composition: a corner patch and three-finger sweeps across edges on bodies
    with edges, patches on round ones (module docstring)."""
    if explorer.rough.has_edges:
        n_corner = max(count // 7, 6)
        index = explorer.scene.hand.index
        explorer.probe_patch(index, corner_probes(explorer.rough, PAPER_CORNER, n_corner, rng))
        _sweeps(explorer, count, rng, PAPER_EDGES, None, THUMB_PROBES)
    else:
        _patches(explorer, count, rng, ROUND_PATCHES)
    _fill(explorer, count, rng)


__all__ = ["paper_strategy", "patch_strategy", "stripe_strategy", "sweep_strategy"]
