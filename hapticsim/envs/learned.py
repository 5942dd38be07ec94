"""Trained actors as small ``.npz`` files with a numpy forward pass (no torch needed to run them).

A weight file holds the layers of a multilayer perceptron (the deterministic actor of a
stable-baselines3 / sb3-contrib model: SAC, TQC, CrossQ or PPO) and, in its ``meta`` entry (a
JSON string), what it was trained for: the environment version (``env_id``), the observation and
action sizes, the environment settings, and the training record (algorithm, steps, seed, wall
time, command). :func:`load_actor` checks all of it; :meth:`Actor.check_settings` checks an
environment's settings against the trained ones. The lab's
:func:`lab.training.export.actor_from_sb3` makes one from a trained model (needs torch).

Layers (``meta["layers"]``, applied in order to an observation vector):

- ``"linear"``: ``x @ W.T + b`` (two arrays, W of shape (out, in));
- ``"relu"``, ``"tanh"``: element-wise;
- ``"batch_renorm"``: ``(x - mean) / sqrt(var + eps) * scale + bias`` (CrossQ's BatchRenorm in
  evaluation mode; four arrays, eps in ``meta["batch_renorm_eps"]``);

then the output squash ``meta["squash"]``: ``"tanh"`` (SAC, TQC, CrossQ) or ``"clip"`` to
[-1, 1] (PPO's mean action).

Set encoders (format version 2, ``meta["sets"]``): the observation's tail holds sets of
elements (``offset``, ``count`` elements of ``width`` numbers, the last 1 where an element is
present), as ``hapticsim/HapticExploreTouch-v0``'s contacts and touches. Each set's own layers
map every present element (its numbers but the last) to a feature vector, pooled by the maximum
and the mean over the present elements (zeros for an empty set); the MLP above then takes the
observation's head (the entries before the first set) and every set's pooled features, in
order. The result does not depend on the order of a set's elements.
"""

from __future__ import annotations

import io
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._files import atomic_write
from hapticsim.envs.registration import canonical_id
from hapticsim.errors import ChoiceError, InvalidInputError

Array = NDArray[np.float64]

#: ``meta["format"]`` of a weight file.
FORMAT: str = "hapticsim-actor"
#: Version of the file format this code writes for a plain MLP.
FORMAT_VERSION: int = 1
#: Version it writes for an actor with set encoders.
SETS_FORMAT_VERSION: int = 2
#: Versions of the file format this code reads.
READ_VERSIONS: tuple[int, ...] = (FORMAT_VERSION, SETS_FORMAT_VERSION)
#: Layer kinds and how many arrays each takes.
LAYER_ARRAYS: dict[str, int] = {"linear": 2, "relu": 0, "tanh": 0, "batch_renorm": 4}
#: Output squashes.
SQUASHES: tuple[str, ...] = ("tanh", "clip")
#: Environment settings that change what an observation or action means: a policy runs only on
#: environments whose settings equal the trained ones (backend, objects, noise and budget may
#: differ).
MEANING_SETTINGS: tuple[str, ...] = ("obs_scale", "max_stroke", "stroke_spacing")
#: The v0 settings a weight file records of the environment it was trained on
#: (:func:`recorded_settings`).
RECORDED_SETTINGS: tuple[str, ...] = (
    "backend", "touch_budget", "noise", "obs_scale", "max_stroke", "stroke_spacing",
    "position_noise", "max_contacts", "support", "sensing",
)  # fmt: skip


def _check_layers(layers: tuple[str, ...], params: tuple[Array, ...], width: int | None) -> None:
    """Check a layer stack's arrays (`width`: its input size, None: any)."""
    unknown = [k for k in layers if k not in LAYER_ARRAYS]
    if unknown:
        raise InvalidInputError(f"`layers` must be kinds from {tuple(LAYER_ARRAYS)}, got {unknown}")
    expected = sum(LAYER_ARRAYS[k] for k in layers)
    if len(params) != expected:
        raise InvalidInputError(
            f"`params` must hold {expected} arrays for layers {list(layers)}, got {len(params)}"
        )
    for i, p in enumerate(params):
        if not np.all(np.isfinite(p)):
            raise InvalidInputError(f"`params[{i}]` holds NaN or infinite values")
    if not any(kind == "linear" for kind in layers):
        raise InvalidInputError("an actor needs at least one linear layer")
    k = 0
    for kind in layers:
        arrays = params[k : k + LAYER_ARRAYS[kind]]
        k += LAYER_ARRAYS[kind]
        if kind == "linear":
            w, b = arrays
            if w.ndim != 2 or b.shape != (w.shape[0],):
                raise InvalidInputError(
                    f"a linear layer needs W (out, in) and b (out,), got {w.shape}, {b.shape}"
                )
            if width is not None and w.shape[1] != width:
                raise InvalidInputError(
                    f"a linear layer takes {w.shape[1]} inputs after a layer of {width}"
                )
            width = w.shape[0]
        elif kind == "batch_renorm":
            if width is not None and any(a.shape != (width,) for a in arrays):
                raise InvalidInputError(f"a batch_renorm layer needs four ({width},) arrays")
            if np.any(arrays[1] < 0):
                raise InvalidInputError("a batch_renorm layer has a negative variance")


def _apply(layers: tuple[str, ...], params: tuple[Array, ...], x: Array, eps: float) -> Array:
    """A layer stack applied to the last axis of `x`."""
    k = 0
    for kind in layers:
        arrays = params[k : k + LAYER_ARRAYS[kind]]
        k += LAYER_ARRAYS[kind]
        if kind == "linear":
            x = x @ arrays[0].T + arrays[1]
        elif kind == "relu":
            x = np.maximum(x, 0.0)
        elif kind == "tanh":
            x = np.tanh(x)
        else:
            mean, var, scale, bias = arrays
            x = (x - mean) / np.sqrt(var + eps) * scale + bias
    return x


def _as_params(params: Any) -> tuple[Array, ...]:
    return tuple(np.asarray(p, dtype=np.float64) for p in params)


@dataclass(frozen=True, eq=False)
class SetEncoder:
    """A permutation-invariant encoder of one set in the observation (module docstring).

    Attributes:
        offset: where the set starts in the observation vector.
        count: its elements.
        width: numbers per element, the last one 1 where the element is present.
        layers: layer kinds of the per-element network (input ``width - 1``).
        params: their arrays.
    """

    offset: int
    count: int
    width: int
    layers: tuple[str, ...]
    params: tuple[Array, ...]

    def __post_init__(self) -> None:
        for name in ("offset", "count", "width"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
                raise InvalidInputError(f"a set's `{name}` must be an int >= 0, got {value!r}")
        if self.count < 1 or self.width < 2:
            raise InvalidInputError(
                f"a set needs count >= 1 and width >= 2, got {self.count} and {self.width}"
            )
        object.__setattr__(self, "layers", tuple(self.layers))
        object.__setattr__(self, "params", _as_params(self.params))
        _check_layers(self.layers, self.params, self.width - 1)

    @property
    def end(self) -> int:
        """Where the set ends in the observation vector."""
        return int(self.offset + self.count * self.width)

    @property
    def features(self) -> int:
        """Length of the pooled features (maximum and mean of the per-element network's
        output)."""
        last_weight = [p for p in self.params if p.ndim == 2][-1]
        return 2 * int(last_weight.shape[0])

    def __call__(self, x: Array, eps: float) -> Array:
        """(n, features) pooled features of a batch of observations (n, obs_dim)."""
        e = x[:, self.offset : self.end].reshape(len(x), self.count, self.width)
        present = e[:, :, -1:] > 0.5
        h = _apply(self.layers, self.params, e[:, :, :-1], eps)
        n = present.sum(axis=1)
        top = np.where(present, h, -np.inf).max(axis=1)
        top = np.where(n > 0, top, 0.0)
        mean = np.where(present, h, 0.0).sum(axis=1) / np.maximum(n, 1)
        return np.concatenate([top, mean], axis=1)

    def record(self) -> dict[str, Any]:
        """Its entry in ``meta["sets"]``."""
        return {"offset": int(self.offset), "count": int(self.count), "width": int(self.width),
                "layers": list(self.layers)}  # fmt: skip


@dataclass(frozen=True, eq=False)
class Actor:
    """A deterministic actor: an MLP from observation to action (with set encoders in front of
    it, if any), and what it was trained for.

    Attributes:
        layers: layer kinds (:data:`LAYER_ARRAYS`), in order.
        params: the arrays of the layers, in order (float64).
        squash: ``"tanh"`` or ``"clip"``.
        meta: the file's record: ``env_id``, ``obs_dim``, ``action_dim``, ``settings``
            (environment settings), ``training`` (algorithm, steps, seed, wall time, command).
        sets: the set encoders (:class:`SetEncoder`), which must follow one another to the
            observation's end; none: the MLP takes the observation.
    """

    layers: tuple[str, ...]
    params: tuple[Array, ...]
    squash: str
    meta: dict[str, Any] = field(default_factory=dict)
    sets: tuple[SetEncoder, ...] = ()

    def __post_init__(self) -> None:
        if self.squash not in SQUASHES:
            raise ChoiceError("squash", self.squash, SQUASHES)
        object.__setattr__(self, "layers", tuple(self.layers))
        object.__setattr__(self, "params", _as_params(self.params))
        object.__setattr__(self, "sets", tuple(self.sets))
        width = None
        if self.sets:
            for a, b in zip(self.sets[:-1], self.sets[1:], strict=True):
                if b.offset != a.end:
                    raise InvalidInputError(
                        f"the sets must follow one another: one ends at {a.end}, the next "
                        f"starts at {b.offset}"
                    )
            width = self.sets[0].offset + sum(e.features for e in self.sets)
        _check_layers(self.layers, self.params, width)

    @property
    def obs_dim(self) -> int:
        """Length of the observation vector."""
        if self.sets:
            return self.sets[-1].end
        return int(self.params[self._first_linear()].shape[1])

    @property
    def action_dim(self) -> int:
        """Length of the action vector."""
        last = max(i for i, _ in self._linear_params())
        return int(self.params[last].shape[0])

    def _linear_params(self) -> list[tuple[int, str]]:
        out, k = [], 0
        for kind in self.layers:
            if kind == "linear":
                out.append((k, kind))
            k += LAYER_ARRAYS[kind]
        return out

    def _first_linear(self) -> int:
        return self._linear_params()[0][0]

    def __call__(self, obs: Any) -> NDArray[np.float32]:
        """The action of one observation, or of a batch.

        Args:
            obs: (obs_dim,) or (n, obs_dim) float.

        Returns:
            (action_dim,) or (n, action_dim) float32 in [-1, 1].
        """
        x = np.asarray(obs, dtype=np.float64)
        if x.shape[-1:] != (self.obs_dim,) or x.ndim > 2:
            raise InvalidInputError(
                f"`obs` must be ({self.obs_dim},) or (n, {self.obs_dim}) float, got {x.shape}"
            )
        eps = float(self.meta.get("batch_renorm_eps", 1e-3))
        if self.sets:
            batch = x.reshape(-1, self.obs_dim)
            z = np.concatenate(
                [batch[:, : self.sets[0].offset], *(e(batch, eps) for e in self.sets)], axis=1
            )
            x = z.reshape(x.shape[:-1] + z.shape[-1:])
        x = _apply(self.layers, self.params, x, eps)
        x = np.tanh(x) if self.squash == "tanh" else np.clip(x, -1.0, 1.0)
        return x.astype(np.float32)

    def describe(self) -> str:
        """What the actor was trained for, in words (for messages)."""
        settings = self.meta.get("settings", {})
        shown = ", ".join(f"{k}={settings[k]!r}" for k in sorted(settings) if k in MEANING_SETTINGS)
        return (
            f"{self.meta.get('env_id', '?')} with observation size {self.obs_dim} and action "
            f"size {self.action_dim}" + (f" ({shown})" if shown else "")
        )

    def check_settings(self, settings: dict[str, Any], where: str = "the environment") -> None:
        """Refuse environment settings that change what observations and actions mean.

        Args:
            settings: the environment's settings (:data:`MEANING_SETTINGS` are compared).
            where: how the environment is named in the message.

        Raises:
            InvalidInputError: a setting differs (the message says what the actor was trained
                for).
        """
        trained = self.meta.get("settings", {})
        for name in MEANING_SETTINGS:
            if name in trained and name in settings:
                if not np.isclose(float(trained[name]), float(settings[name]), rtol=1e-9):
                    raise InvalidInputError(
                        f"the policy was trained for {self.describe()}; {where} has "
                        f"{name}={settings[name]!r}"
                    )

    def to_bytes(self) -> bytes:
        """The ``.npz`` file's content."""
        meta = dict(self.meta)
        meta.pop("sets", None)
        meta.update(
            format=FORMAT, format_version=SETS_FORMAT_VERSION if self.sets else FORMAT_VERSION,
            layers=list(self.layers), squash=self.squash, obs_dim=self.obs_dim,
            action_dim=self.action_dim,
        )  # fmt: skip
        arrays = {f"param_{i}": p.astype(np.float32) for i, p in enumerate(self.params)}
        if self.sets:
            meta["sets"] = [e.record() for e in self.sets]
            for j, e in enumerate(self.sets):
                arrays.update({f"set{j}_param_{i}": p.astype(np.float32)
                               for i, p in enumerate(e.params)})  # fmt: skip
        buf = io.BytesIO()
        np.savez_compressed(buf, meta=np.array(json.dumps(meta, sort_keys=True)), **arrays)
        return buf.getvalue()

    def save(self, path: str | Path) -> Path:
        """Write the weight file atomically (``.npz``); returns its path."""

        path = Path(path)
        if path.suffix != ".npz":
            raise InvalidInputError(f"`path` must end in .npz, got {str(path)!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        data = self.to_bytes()
        return atomic_write(path, lambda fh: fh.write(data), "wb")


def load_actor(
    path: str | Path,
    env_id: str | None = None,
    obs_dim: int | None = None,
    action_dim: int | None = None,
) -> Actor:
    """Read a weight file and check what it was trained for.

    Args:
        path: the ``.npz`` file.
        env_id: the environment version the caller runs (None: any).
        obs_dim: the observation size the caller gives (None: any).
        action_dim: the action size the caller expects (None: any).

    Raises:
        InvalidInputError: a missing or unreadable file, another format, or an actor trained for
            another environment version, observation or action size (the message says what it
            was trained for).
    """
    path = Path(path)
    if not path.is_file():
        raise InvalidInputError(f"policy weights file {str(path)!r} does not exist")
    try:
        with np.load(path, allow_pickle=False) as data:
            files = dict(data.items())
    except (OSError, ValueError) as exc:
        raise InvalidInputError(
            f"policy weights file {str(path)!r} is not a readable .npz file: {exc}"
        ) from None
    if "meta" not in files:
        raise InvalidInputError(f"policy weights file {str(path)!r} has no `meta` entry")
    try:
        meta = json.loads(str(files["meta"]))
        if not isinstance(meta, dict):
            raise ValueError("not a JSON object")
    except ValueError as exc:
        raise InvalidInputError(f"policy weights file {str(path)!r}: bad `meta`: {exc}") from None
    if meta.get("format") != FORMAT:
        raise InvalidInputError(
            f"policy weights file {str(path)!r} is not a {FORMAT} file (format "
            f"{meta.get('format')!r})"
        )
    if meta.get("format_version") not in READ_VERSIONS:
        raise InvalidInputError(
            f"policy weights file {str(path)!r} has format version "
            f"{meta.get('format_version')!r}; this hapticsim reads versions {READ_VERSIONS}"
        )
    layers = meta.get("layers")
    if not isinstance(layers, list) or not all(isinstance(k, str) for k in layers):
        raise InvalidInputError(f"policy weights file {str(path)!r}: `layers` must be a list")
    count = sum(LAYER_ARRAYS.get(k, 0) for k in layers)
    missing = [f"param_{i}" for i in range(count) if f"param_{i}" not in files]
    if missing:
        raise InvalidInputError(f"policy weights file {str(path)!r} lacks arrays {missing}")
    try:
        sets = tuple(
            _read_set(files, j, record) for j, record in enumerate(meta.pop("sets", None) or [])
        )
        actor = Actor(
            tuple(layers),
            tuple(files[f"param_{i}"] for i in range(count)),
            str(meta.get("squash")),
            meta,
            sets,
        )
    except InvalidInputError as exc:
        raise InvalidInputError(f"policy weights file {str(path)!r}: {exc}") from None
    wanted = []
    if env_id is not None and canonical_id(str(meta.get("env_id"))) != canonical_id(env_id):
        wanted.append(f"{env_id}")
    if obs_dim is not None and actor.obs_dim != obs_dim:
        wanted.append(f"observation size {obs_dim}")
    if action_dim is not None and actor.action_dim != action_dim:
        wanted.append(f"action size {action_dim}")
    if wanted:
        raise InvalidInputError(
            f"policy weights file {str(path)!r} was trained for {actor.describe()}; this "
            f"hapticsim runs learned policies for {', '.join(wanted)}"
        )
    return actor


def _read_set(files: dict[str, Any], j: int, record: Any) -> SetEncoder:
    """Set encoder `j` of a weight file."""
    if not isinstance(record, dict) or not isinstance(record.get("layers"), list):
        raise InvalidInputError(f"`sets[{j}]` must be a record with `layers`")
    count = sum(LAYER_ARRAYS.get(k, 0) for k in record["layers"])
    missing = [f"set{j}_param_{i}" for i in range(count) if f"set{j}_param_{i}" not in files]
    if missing:
        raise InvalidInputError(f"lacks arrays {missing}")
    return SetEncoder(
        record.get("offset"), record.get("count"), record.get("width"), tuple(record["layers"]),
        tuple(files[f"set{j}_param_{i}"] for i in range(count)),
    )  # fmt: skip


