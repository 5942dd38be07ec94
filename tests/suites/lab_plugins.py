"""Plug-ins as a lab would write them, for the suite tests (imported by name in workers)."""

from __future__ import annotations

import os

import numpy as np

from hapticsim.fitting import fit


def _unlucky(points: np.ndarray) -> bool:
    """About one case in three, decided by the data (the same cases every run)."""
    return int(abs(points[0, 0]) * 1e7) % 3 == 0


def nh_fit(points: np.ndarray, normals: np.ndarray):  # noqa: ANN201
    """The built-in nH with a fixed seed, as a plug-in returning a Superquadric."""
    return fit(points, normals, method="nH", rng=0).superquadric


def spec_dict_fit(points: np.ndarray, normals: np.ndarray) -> dict:
    """Returns the SPEC §6 dict of a fit result (the ``hapticsim fit`` JSON layout)."""
    return fit(points, normals, method="nLS").to_dict()


def garbage_fit(points: np.ndarray, normals: np.ndarray):  # noqa: ANN201
    """Returns garbage on some cases: a dict without ``eps``, or a string."""
    if _unlucky(points):
        return {"a": [0.03, 0.03, 0.03]}
    if int(abs(points[0, 1]) * 1e7) % 5 == 0:
        return "not a superquadric"
    return nh_fit(points, normals)


def raising_fit(points: np.ndarray, normals: np.ndarray):  # noqa: ANN201
    """Raises on some cases."""
    if _unlucky(points):
        raise RuntimeError("no convergence (as a lab's fitter might say)")
    return nh_fit(points, normals)


def nan_fit(points: np.ndarray, normals: np.ndarray) -> dict:
    """Returns a superquadric full of NaN."""
    return {"a": [float("nan")] * 3, "eps": [1.0, 1.0], "rotation": np.eye(3).tolist(),
            "center": [0.0, 0.0, 0.0]}  # fmt: skip


def dying_fit(points: np.ndarray, normals: np.ndarray):  # noqa: ANN201
    """Kills its worker process (as a crash in native code would) on cases of 149 contacts."""
    if len(points) == 149:
        os._exit(3)
    return fit(points, method="LS").superquadric


def three_args(points: np.ndarray, normals: np.ndarray, extra: int):  # noqa: ANN201
    """Cannot be called as fit(points, normals)."""
    return None


NOT_CALLABLE = 42


class NotAPolicy:
    """Instances cannot be called."""

    def __init__(self, env, rng=None) -> None:  # noqa: ANN001
        self.env = env


class BadActionPolicy:
    """Returns actions of the wrong shape."""

    def __init__(self, env, rng=None) -> None:  # noqa: ANN001
        self.env = env

    def __call__(self, obs):  # noqa: ANN001, ANN204
        return np.zeros(2, dtype=np.float32)
