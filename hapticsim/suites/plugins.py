"""User plug-ins: a lab's own fitter or policy, named ``MODULE:ATTRIBUTE`` on the command line.

- ``--fitter my_lab.fitting:fit``: a callable ``fit(points, normals)`` with points and normals
  (n, 3) float arrays [m, world; unit outward normals], returning a
  :class:`~hapticsim.geometry.Superquadric`, a :class:`~hapticsim.fitting.FitResult`, or a dict in
  the SPEC §6 form (a bare superquadric, or a fit result with a ``superquadric`` key).
- ``--policy my_lab.policies:Policy``: a class with the interface of the baseline policies
  (:class:`hapticsim.envs.policies.Policy`): ``Policy(env, rng=seed)``, ``policy.reset(rng)`` at
  each episode start, ``action = policy(observation)``.

The module is imported with the working directory on ``sys.path`` (as ``python -m`` would), in
this process to check it and again in every worker; on a remote Dask cluster it must be
importable on the workers too.
"""

from __future__ import annotations

import hashlib
import importlib
import inspect
import os
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Solid, solid_from_dict

_SPEC = re.compile(r"[A-Za-z_]\w*(\.[A-Za-z_]\w*)*:[A-Za-z_]\w*(\.[A-Za-z_]\w*)*")
_LOADED: dict[str, Any] = {}


def resolve(spec: str, option: str) -> Any:
    """The object named by ``MODULE:ATTRIBUTE``, imported (cached per process).

    Args:
        spec: e.g. ``"my_lab.fitting:fit"``.
        option: the command-line option, for messages (``"fitter"``, ``"policy"``).

    Raises:
        InvalidInputError: malformed spec, a module that fails to import (its error is quoted),
            or a missing attribute.
    """
    if spec in _LOADED:
        return _LOADED[spec]
    if not isinstance(spec, str) or not _SPEC.fullmatch(spec):
        raise InvalidInputError(
            f"--{option} must be MODULE:ATTRIBUTE, e.g. my_lab.fitting:fit, got {spec!r}"
        )
    module_name, attr = spec.split(":")
    cwd = os.getcwd()
    if cwd not in sys.path:
        sys.path.insert(0, cwd)
    try:
        module = importlib.import_module(module_name)
    except Exception as exc:  # ImportError, SyntaxError, or anything the module raised
        detail = " ".join(str(exc).split())
        raise InvalidInputError(
            f"--{option} {spec}: cannot import module {module_name!r} "
            f"({type(exc).__name__}: {detail})"
        ) from None
    value: Any = module
    for part in attr.split("."):
        if not hasattr(value, part):
            raise InvalidInputError(f"--{option} {spec}: module {module_name!r} has no {attr!r}")
        value = getattr(value, part)
    _LOADED[spec] = value
    return value


def load_fitter(spec: str) -> Callable[[Any, Any], Any]:
    """The fitter of ``--fitter MODULE:FUNCTION``, checked to be callable as ``fit(p, n)``.

    Raises:
        InvalidInputError: see :func:`resolve`; or not callable with two arguments.
    """
    fitter = resolve(spec, "fitter")
    if not callable(fitter):
        raise InvalidInputError(f"--fitter {spec}: {type(fitter).__name__} is not callable")
    try:
        inspect.signature(fitter).bind(None, None)
    except TypeError:
        raise InvalidInputError(
            f"--fitter {spec}: must accept (points, normals), its signature is "
            f"{inspect.signature(fitter)}"
        ) from None
    except ValueError:  # builtins without a signature: accept
        pass
    return fitter


def load_policy(spec: str) -> type:
    """The policy class of ``--policy MODULE:CLASS``, checked for the baseline interface.

    Raises:
        InvalidInputError: see :func:`resolve`; not a class; instances not callable; or a
            constructor that does not take ``(env, rng=...)``.
    """
    cls = resolve(spec, "policy")
    if not isinstance(cls, type):
        raise InvalidInputError(
            f"--policy {spec}: must be a class like hapticsim.envs.policies.Policy, got "
            f"{type(cls).__name__}"
        )
    if not any("__call__" in vars(base) for base in cls.__mro__ if base is not object):
        raise InvalidInputError(
            f"--policy {spec}: instances must be callable: action = policy(obs)"
        )
    try:
        inspect.signature(cls).bind(None, rng=0)
    except TypeError:
        raise InvalidInputError(
            f"--policy {spec}: the constructor must accept (env, rng=...), its signature is "
            f"{inspect.signature(cls)}"
        ) from None
    return cls


def make_plugin_policy(spec: str, env: Any, seed: int) -> Any:
    """A lab's policy ``MODULE:CLASS`` made for `env` with `seed`, and reset with it where it is
    not a :class:`~hapticsim.envs.policies.Policy` (whose episodes reset it themselves).

    Raises:
        InvalidInputError: see :func:`load_policy`; what its constructor or reset raises passes
            through.
    """
    from hapticsim.envs.policies import Policy

    policy = load_policy(spec)(env, rng=seed)
    if not isinstance(policy, Policy) and hasattr(policy, "reset"):
        policy.reset(seed)
    return policy


def describe(spec: str | None, option: str) -> dict[str, Any] | None:
    """Provenance of a plug-in: its spec, module file and the file's SHA-256 (None if none)."""
    if spec is None:
        return None
    module = sys.modules.get(spec.split(":")[0])
    path = getattr(module, "__file__", None)
    digest = None
    if path and Path(path).is_file():
        digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    return {"option": option, "spec": spec, "file": path, "sha256": digest}


def as_solid(value: Any) -> Any:
    """A fitter's return value as a solid (:class:`~hapticsim.geometry.solid.Solid`).

    Accepts a solid (a Superquadric, a SuperquadricUnion, ...), anything with a ``solid`` or a
    ``superquadric`` attribute holding one (a ``FitResult``), or a SPEC §6 or §10 dict (bare,
    or a fit result with a ``solid`` or ``superquadric`` key).

    Raises:
        InvalidInputError: anything else, or a dict that is not a valid superquadric or union.
    """

    if isinstance(value, Solid):
        return value
    for attribute in ("solid", "superquadric"):
        inner = getattr(value, attribute, None)
        if isinstance(inner, Solid):
            return inner
    if isinstance(value, dict):
        try:
            return solid_from_dict(value)
        except InvalidInputError as exc:
            raise InvalidInputError(f"the fitter returned an invalid solid: {exc}") from None
        except (TypeError, ValueError) as exc:
            raise InvalidInputError(
                f"the fitter returned an invalid solid: {type(exc).__name__}: {exc}"
            ) from None
    shown = repr(value)
    shown = shown if len(shown) <= 60 else shown[:57] + "..."
    raise InvalidInputError(
        f"the fitter returned {type(value).__name__} {shown}: expected a Superquadric, a "
        "SuperquadricUnion, a FitResult or a SPEC §6/§10 dict"
    )
