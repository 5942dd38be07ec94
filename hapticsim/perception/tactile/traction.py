"""The skin's traction field: normal pressure and tangential traction on every taxel, with
Coulomb friction and partial slip (SPEC §11).

**Model.** The skin layer is a brush in shear as it is a Winkler foundation in compression: a
taxel's patch of skin sheared by u carries the traction ``q = G u / h`` on its own, and where the
object's surface sticks to the skin every patch is sheared by the same rigid tangential
displacement, so every sticking taxel carries the same traction ``c``. Coulomb's law bounds each
taxel, ``|q| <= mu p``: a taxel whose bound is below ``c`` slips and carries ``mu p`` instead.
Under a tangential load Q (along the load's direction, the same for every taxel) the common
traction c solves

    sum_i A_i min(c, mu p_i) = Q,

so a contact sticks where its pressure is high and slips where it is low: the slip region grows
from the contact's edge inward as the load rises, and the whole contact slides once Q reaches
``mu N`` (N = sum_i A_i p_i). For a sphere in a thin layer (Winkler pressure ``p0 (1 - r^2 /
a^2)``) the stick region is the disc ``r < a (1 - Q / (mu N))^(1/4)`` (the thin layer's
counterpart of Cattaneo and Mindlin's ``(1 - Q / (mu N))^(1/3)`` for a half-space);
:func:`winkler_stick_radius`.

The model is quasi-static and holds for a load that rises in one direction (a press, then a
stroke); unloading and reversals, whose tractions depend on the path, are not modelled. The
tangential load is given as a share of the friction limit, ``Q / (mu N)``, so that the physics
that loads the contact (MuJoCo's friction force against its normal force, or a stroke's
sliding) sets how far the contact is from sliding while the skin's own pressure sets how the
traction is spread.

numpy only.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]

#: A taxel's state (``tactile.npz`` ``taxel_state``): not in contact.
TAXEL_FREE: int = 0
#: A taxel in contact that sticks to the object.
TAXEL_STICK: int = 1
#: A taxel in contact that slips (its traction at Coulomb's bound ``mu p``).
TAXEL_SLIP: int = 2
#: The states' names, by value.
TAXEL_STATES: tuple[str, ...] = ("free", "stick", "slip")


def traction_field(
    pressure: Array, load: Array, friction: float, area: Array | None = None
) -> tuple[Array, NDArray[np.int8]]:
    """Every taxel's traction and state (module docstring).

    Args:
        pressure: (..., rows, cols) float, the skin's normal pressure [Pa] (one image per pad;
            taxels at 0 are not in contact).
        load: (..., 2) float, each image's tangential load as a share of its friction limit,
            ``Q / (mu N)``, in the pad's (u, v) axes: its direction is the traction's, its
            length (clipped to 1) how far the contact is from sliding (1: it slides).
        friction: Coulomb's coefficient mu, >= 0 (0: every contact taxel slips, carrying
            nothing).
        area: (rows, cols) float, the taxels' areas [m^2] (None: equal).

    Returns:
        ``traction`` (..., rows, cols, 3): the pressure, then the tangential traction along
        the pad's u and v [Pa]; ``state`` (..., rows, cols) int8: :data:`TAXEL_FREE`,
        :data:`TAXEL_STICK` or :data:`TAXEL_SLIP`.

    Raises:
        InvalidInputError: shapes that do not match, a negative or non-finite friction, NaN.
    """
    p = np.asarray(pressure, dtype=np.float64)
    rho = np.asarray(load, dtype=np.float64)
    mu = float(friction)
    if p.ndim < 2 or rho.shape != (*p.shape[:-2], 2):
        raise InvalidInputError(
            f"`load` must be (..., 2) for pressure images (..., rows, cols): got {rho.shape} "
            f"for {p.shape}"
        )
    if not (np.isfinite(mu) and mu >= 0.0):
        raise InvalidInputError(f"`friction` must be finite and >= 0, got {friction!r}")
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(rho))):
        raise InvalidInputError("pressure and load must be finite")
    rows, cols = p.shape[-2:]
    w = np.ones((rows, cols)) if area is None else np.asarray(area, dtype=np.float64)
    if w.shape != (rows, cols):
        raise InvalidInputError(f"`area` must be {(rows, cols)}, got {w.shape}")
    lead = p.shape[:-2]
    flat_p = np.maximum(p.reshape(-1, rows * cols), 0.0)
    flat_rho = rho.reshape(-1, 2)
    traction = np.zeros((flat_p.shape[0], rows * cols, 3))
    state = np.zeros((flat_p.shape[0], rows * cols), dtype=np.int8)
    weights = w.ravel()
    for k in range(flat_p.shape[0]):
        touching = flat_p[k] > 0.0
        traction[k, :, 0] = flat_p[k]
        if not touching.any():
            continue
        share = float(np.hypot(*flat_rho[k]))
        bound = mu * flat_p[k]
        if mu == 0.0 or share >= 1.0:
            common = np.inf
        else:
            common = _common_traction(bound[touching], weights[touching], share)
        q = np.minimum(common, bound)
        state[k] = np.where(touching, np.where(bound > common, TAXEL_STICK, TAXEL_SLIP),
                            TAXEL_FREE)  # fmt: skip
        if share > 0.0:
            direction = flat_rho[k] / share
            traction[k, :, 1:] = q[:, None] * direction[None, :]
    return (traction.reshape(*lead, rows, cols, 3), state.reshape(*lead, rows, cols))


def _common_traction(bound: Array, weights: Array, share: float) -> float:
    """The traction c of the sticking taxels: ``sum w min(c, b) = share * sum w b`` (b the
    taxels' Coulomb bounds, share in [0, 1))."""
    order = np.argsort(bound)
    b, w = bound[order], weights[order]
    target = share * float(np.sum(w * b))
    below = np.concatenate([[0.0], np.cumsum(w * b)])  # carried by taxels 0..k-1 at their bound
    above = np.concatenate([np.cumsum(w[::-1])[::-1], [0.0]])  # weight of taxels k..n-1
    # carried when c = b[k]: the taxels below k slip, those from k on carry b[k]
    at = below[:-1] + b * above[:-1]
    k = int(np.searchsorted(at, target, side="right"))  # first k with at[k] > target
    return float((target - below[k]) / above[k]) if k < len(b) else float(b[-1])


def contact_share(traction: Array, state: NDArray[np.int8], friction: float,
                  area: Array | None = None) -> tuple[float, float]:  # fmt: skip
    """One image's tangential force as a share of its friction limit, ``|Q| / (mu N)``, and
    the share of its contact taxels that slip (both 0 without contact)."""
    t = np.asarray(traction, dtype=np.float64)
    w = np.ones(t.shape[:-1]) if area is None else np.asarray(area, dtype=np.float64)
    normal = float(np.sum(w * t[..., 0]))
    touching = state > TAXEL_FREE
    if normal <= 0.0 or not touching.any():
        return 0.0, 0.0
    q = np.array([np.sum(w * t[..., 1]), np.sum(w * t[..., 2])])
    share = float(np.hypot(*q)) / (friction * normal) if friction > 0 else 1.0
    return share, float(np.mean(state[touching] == TAXEL_SLIP))


def winkler_stick_radius(share: float) -> float:
    """The stick region's radius over the contact radius, for a sphere pressed into a thin
    (Winkler) layer and loaded tangentially by ``share = Q / (mu N)`` in [0, 1]:
    ``(1 - share)^(1/4)`` (module docstring)."""
    s = float(np.clip(share, 0.0, 1.0))
    return float((1.0 - s) ** 0.25)


__all__ = [
    "TAXEL_FREE",
    "TAXEL_SLIP",
    "TAXEL_STATES",
    "TAXEL_STICK",
    "contact_share",
    "traction_field",
    "winkler_stick_radius",
]
