"""Hand descriptions: which MJCF hand to use and how hapticsim drives it (a small TOML file).

A description names the model file, the *root* body that the mocap palm holds, the fingers
(thumb first) with their fingertip body, tip centre and touching geom, the joints the fingertip
controllers drive, the actuators (the model's, or position actuators that hapticsim adds), and
three joint postures per finger. Shipped descriptions (:data:`HAND_NAMES`): ``hapticsim`` (our
four-fingered hand, the default), ``shadow`` and ``adroit`` (the models installed by
gymnasium-robotics, the optional extra ``hands``). ``docs/hands.md`` explains the format; a
minimal file::

    name = "myhand"
    model = "myhand.xml"          # a path (relative to this file), or "package:path/in/it"
    root = "palm"                 # welded to the mocap palm

    [actuation]
    mode = "add"                  # "model": use `actuators`; "add": position actuators
    kp = 3.0                      # [N m/rad] of the added actuators
    kv = 0.05                     # [N m s/rad]
    joint_margin = 0.02           # [rad] kept from the joint limits

    [[fingers]]
    name = "thumb"
    thumb = true                  # the thumb, listed first
    body = "thumb_distal"         # fingertip body
    site = "thumb_tip"            # tip centre (or tip_pos = [x, y, z] in the body frame [m])
    tip_radius = 0.009            # [m]; without `geom` a sphere of this radius is added
    joints = ["th_j1", "th_j2", "th_j3"]   # driven joints, palm outwards
    tucked = [0.0, 1.4, 1.5]      # postures [rad], one value per joint
    probe = [0.0, 0.3, 1.3]
    sweep = [0.0, 0.35, 1.7]
    pad = { normal = [0.8, 0.0, 0.6] }   # optional: its taxel pad (see below)

Tactile pads (``hapticsim explore --sensing tactile``; SPEC §9, §11): the optional top-level
``[pad]`` table sets the grid every fingertip's pad has (``rows``, ``cols``, ``pitch`` [m];
default :data:`DEFAULT_PAD_GRID`, 31 x 31 taxels 1 mm apart), and a finger's ``pad`` table
where it sits: ``on`` (a geom or site of the fingertip body; default the touching geom),
``normal`` (the outward direction at the pad's centre, in that element's frame; default the
fingertip's pulp, between its pointing and flexion directions), ``up`` (the rows' direction),
``radius`` [m] (the sphere it follows: a sphere or capsule geom's own radius by default, the
finger's `tip_radius` on a site) or ``flat = true`` (a plate). A pad follows the fingertip's
curvature: a sphere, the end cap of a capsule, or a flat plate.

Model files are never copied: ``"gymnasium_robotics:envs/assets/hand/reach.xml"`` is read from
the installed package, ``"hapticsim:hand.xml"`` from hapticsim's models directory.

Validation (:func:`load_hand`) reads the model and names what is missing or wrong:
``hand 'shadow', finger 'ff': no body 'robot0:ffdistal' in reach.xml``.
"""

from __future__ import annotations

import importlib.util
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import mujoco

from hapticsim._files import named_toml, read_toml
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.perception.tactile.pad import DEFAULT_PAD_GRID
from hapticsim.sim.models import models_dir

#: Names of the shipped hand descriptions (``hapticsim/hands/<name>.toml``).
HAND_NAMES: tuple[str, ...] = ("hapticsim", "shadow", "adroit")
#: The default hand.
DEFAULT_HAND: str = "hapticsim"
#: Postures every finger describes, by name: out of the way, ready to probe (its tip on the
#: expected contact), hooked for an edge-crossing sweep.
POSTURE_NAMES: tuple[str, ...] = ("tucked", "probe", "sweep")
#: Actuation modes.
ACTUATION_MODES: tuple[str, ...] = ("model", "add")
#: Directory of the shipped descriptions.
HANDS_DIR: Path = Path(__file__).resolve().parents[1] / "hands"

_FINGER_KEYS = {
    "name", "thumb", "body", "site", "tip_pos", "geom", "tip_radius", "joints", "actuators",
    "coupled", "pad", *POSTURE_NAMES,
}  # fmt: skip
_TOP_KEYS = {"name", "model", "root", "extra", "actuation", "fingers", "sweep_fingers", "pad"}
_PAD_KEYS = {"on", "normal", "up", "radius", "flat"}
_GRID_KEYS = {"rows", "cols", "pitch"}
_ACTUATION_KEYS = {"mode", "kp", "kv", "joint_margin"}


class HandDescriptionError(InvalidInputError):
    """A hand description that cannot be used; the message names the element."""


@dataclass(frozen=True)
class Coupling:
    """A passive joint that follows a driven one (``q_joint ~ ratio * q_follows``), e.g. the
    distal joint of a Shadow finger, tied to the middle one by a tendon.

    Attributes:
        joint: the passive joint.
        follows: the driven joint of the same finger.
        ratio: dq_joint / dq_follows.
    """

    joint: str
    follows: str
    ratio: float = 1.0


@dataclass(frozen=True)
class PadDescription:
    """Where a finger's taxel pad sits (see the module docstring for the TOML keys).

    Attributes:
        on: the geom or site of the fingertip body that carries it, or None (the finger's
            touching geom).
        normal: (3,) outward direction at the pad's centre in the carrier's frame, or None
            (the fingertip's pulp, :func:`hapticsim.sim.tactile.default_pad_normal`).
        up: (3,) the rows' direction, or None (:func:`hapticsim.perception.tactile.pad.default_up`).
        radius: the radius [m] of the sphere the pad follows, or None (the carrier's own).
        flat: True for a flat plate.
    """

    on: str | None = None
    normal: tuple[float, float, float] | None = None
    up: tuple[float, float, float] | None = None
    radius: float | None = None
    flat: bool = False


@dataclass(frozen=True)
class FingerDescription:
    """One finger of a hand description (see the module docstring for the TOML keys).

    Attributes:
        name: finger name.
        body: fingertip body.
        joints: driven joints, palm outwards.
        postures: (posture name, joint angles [rad]) pairs, one angle per joint, in the order
            of :data:`POSTURE_NAMES`.
        tip_radius: radius of the fingertip [m].
        site: site at the tip centre, or None (then `tip_pos`).
        tip_pos: (3,) tip centre in the fingertip body's frame [m], when there is no site.
        geom: the touching geom of the model, or None (a sphere of `tip_radius` is added).
        actuators: the model's actuators driving `joints` (actuation mode ``"model"``).
        coupled: passive joints following driven ones.
        thumb: True for the thumb.
        pad: where its taxel pad sits.
    """

    name: str
    body: str
    joints: tuple[str, ...]
    postures: tuple[tuple[str, tuple[float, ...]], ...]
    tip_radius: float
    site: str | None = None
    tip_pos: tuple[float, float, float] | None = None
    geom: str | None = None
    actuators: tuple[str, ...] = ()
    coupled: tuple[Coupling, ...] = ()
    thumb: bool = False
    pad: PadDescription = field(default_factory=PadDescription)

    def posture(self, name: str) -> tuple[float, ...]:
        """The joint angles [rad] of a named posture (:data:`POSTURE_NAMES`)."""
        for key, values in self.postures:
            if key == name:
                return values
        raise ChoiceError("posture", name, POSTURE_NAMES)


@dataclass(frozen=True)
class HandDescription:
    """A validated hand description (:func:`load_hand`).

    Attributes:
        name: the hand's name.
        model: the MJCF file.
        root: the body welded to the mocap palm.
        fingers: the fingers, thumb first.
        actuation: ``"model"`` or ``"add"`` (:data:`ACTUATION_MODES`).
        kp: stiffness of added position actuators [N m/rad].
        kv: damping of added position actuators [N m s/rad].
        joint_margin: distance kept from the joint limits [rad].
        sweep_fingers: indices of the fingers that sweep edges (default: the first three
            after the thumb).
        pad_grid: (rows, cols, pitch [m]) of every fingertip's taxel pad.
        source: the TOML file, or None.
    """

    name: str
    model: Path
    root: str
    fingers: tuple[FingerDescription, ...]
    actuation: str = "model"
    kp: float = 3.0
    kv: float = 0.05
    joint_margin: float = 0.0
    sweep_fingers: tuple[int, ...] = ()
    pad_grid: tuple[int, int, float] = DEFAULT_PAD_GRID
    source: Path | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if not self.sweep_fingers:
            rest = tuple(range(1, len(self.fingers)))
            object.__setattr__(self, "sweep_fingers", rest[:3])

    @property
    def finger_names(self) -> tuple[str, ...]:
        """Finger names in index order (0 is the thumb)."""
        return tuple(f.name for f in self.fingers)

    @property
    def key(self) -> tuple[str, str]:
        """What identifies the hand in caches: its name and the resolved model path."""
        return (self.name, str(self.model))


def _err(where: str, message: str) -> HandDescriptionError:
    return HandDescriptionError(f"{where}: {message}")


def _resolve_model(value: Any, where: str, base: Path, extra: str | None) -> Path:
    if not isinstance(value, str) or not value:
        raise _err(where, f"`model` must be a file path or 'package:path', got {value!r}")
    package, sep, inner = value.partition(":")
    if sep and package and "/" not in package and "\\" not in package and len(package) > 1:
        if package == "hapticsim":
            path = models_dir() / inner
        else:
            try:
                spec = importlib.util.find_spec(package)
            except (ImportError, ValueError):  # a broken or half-removed installation
                spec = None
            if spec is None or not spec.submodule_search_locations:
                hint = f" (pip install 'hapticsim[{extra}]')" if extra else ""
                raise _err(
                    where, f"its model is in the Python package {package!r}, which is not "
                    f"installed{hint}",
                )  # fmt: skip
            path = Path(next(iter(spec.submodule_search_locations))) / inner
    else:
        path = Path(value).expanduser()
        if not path.is_absolute():
            path = base / path
    if not path.is_file():
        raise _err(where, f"model file {str(path)!r} not found")
    return path.resolve()


def _float(value: Any, name: str, where: str, low: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise _err(where, f"`{name}` must be a finite number, got {value!r}")
    if low is not None and value < low:
        raise _err(where, f"`{name}` must be >= {low}, got {value!r}")
    return float(value)


def _names(value: Any, name: str, where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise _err(where, f"`{name}` must be a non-empty list of names, got {value!r}")
    return tuple(value)


def _vector(value: Any, name: str, where: str) -> tuple[float, float, float]:
    if not isinstance(value, list) or len(value) != 3:
        raise _err(where, f"`{name}` must be [x, y, z], got {value!r}")
    out = tuple(_float(v, name, where) for v in value)
    if math.hypot(*out) < 1e-9:
        raise _err(where, f"`{name}` must be a non-zero vector, got {value!r}")
    return out  # type: ignore[return-value]


def _pad(raw: Any, where: str) -> PadDescription:
    here = f"{where}, pad"
    if not isinstance(raw, dict):
        raise _err(here, f"`pad` must be a table, got {raw!r}")
    unknown = sorted(set(raw) - _PAD_KEYS)
    if unknown:
        raise _err(here, f"unknown keys {unknown}; the keys are {sorted(_PAD_KEYS)}")
    on = raw.get("on")
    if on is not None and (not isinstance(on, str) or not on):
        raise _err(here, f"`on` must be a geom or site name, got {on!r}")
    flat = raw.get("flat", False)
    if not isinstance(flat, bool):
        raise _err(here, f"`flat` must be true or false, got {flat!r}")
    radius = raw.get("radius")
    if radius is not None:
        radius = _float(radius, "radius", here, low=1e-4)
        if flat:
            raise _err(here, "a flat pad has no `radius`")
    return PadDescription(
        on=on, normal=None if "normal" not in raw else _vector(raw["normal"], "normal", here),
        up=None if "up" not in raw else _vector(raw["up"], "up", here), radius=radius, flat=flat,
    )  # fmt: skip


def _grid(raw: Any, where: str) -> tuple[int, int, float]:
    here = f"{where}, [pad]"
    if not isinstance(raw, dict):
        raise _err(here, f"must be a table, got {raw!r}")
    unknown = sorted(set(raw) - _GRID_KEYS)
    if unknown:
        raise _err(here, f"unknown keys {unknown}; the keys are {sorted(_GRID_KEYS)}")
    rows_d, cols_d, pitch_d = DEFAULT_PAD_GRID
    counts = []
    for key, default in (("rows", rows_d), ("cols", cols_d)):
        value = raw.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise _err(here, f"`{key}` must be a whole number >= 1, got {value!r}")
        counts.append(value)
    pitch = _float(raw.get("pitch", pitch_d), "pitch", here, low=1e-5)
    if pitch > 0.05:
        raise _err(here, f"`pitch` must be at most 0.05 m, got {pitch!r}")
    return counts[0], counts[1], pitch


def _finger(raw: Any, k: int, where: str) -> FingerDescription:
    if not isinstance(raw, dict):
        raise _err(where, f"[[fingers]] entry {k} must be a table, got {raw!r}")
    name = raw.get("name")
    if not isinstance(name, str) or not name:
        raise _err(where, f"[[fingers]] entry {k} needs a `name`")
    here = f"{where}, finger {name!r}"
    unknown = sorted(set(raw) - _FINGER_KEYS)
    if unknown:
        raise _err(here, f"unknown keys {unknown}; the keys are {sorted(_FINGER_KEYS)}")
    for key in ("body", "joints", "tip_radius"):
        if key not in raw:
            raise _err(here, f"`{key}` is missing")
    body = raw["body"]
    if not isinstance(body, str) or not body:
        raise _err(here, f"`body` must be a body name, got {body!r}")
    joints = _names(raw["joints"], "joints", here)
    postures: dict[str, tuple[float, ...]] = {}
    for posture in POSTURE_NAMES:
        values = raw.get(posture)
        if values is None:
            raise _err(here, f"posture `{posture}` is missing (one angle [rad] per joint)")
        if not isinstance(values, list) or len(values) != len(joints):
            raise _err(
                here, f"posture `{posture}` must list {len(joints)} angles [rad] (one per "
                f"joint), got {values!r}",
            )  # fmt: skip
        postures[posture] = tuple(_float(v, posture, here) for v in values)
    site, tip_pos = raw.get("site"), raw.get("tip_pos")
    if (site is None) == (tip_pos is None):
        raise _err(here, "give the tip centre as `site` or as `tip_pos` (one of them)")
    if site is not None and not isinstance(site, str):
        raise _err(here, f"`site` must be a site name, got {site!r}")
    if tip_pos is not None:
        if not isinstance(tip_pos, list) or len(tip_pos) != 3:
            raise _err(here, f"`tip_pos` must be [x, y, z] [m], got {tip_pos!r}")
        tip_pos = tuple(_float(v, "tip_pos", here) for v in tip_pos)
    geom = raw.get("geom")
    if geom is not None and not isinstance(geom, str):
        raise _err(here, f"`geom` must be a geom name, got {geom!r}")
    actuators = _names(raw["actuators"], "actuators", here) if "actuators" in raw else ()
    coupled = []
    for c in raw.get("coupled", []):
        if not isinstance(c, dict) or not {"joint", "follows"} <= set(c):
            raise _err(here, f"`coupled` entries need `joint` and `follows`, got {c!r}")
        coupled.append(
            Coupling(str(c["joint"]), str(c["follows"]), _float(c.get("ratio", 1.0), "ratio", here))
        )
        if coupled[-1].follows not in joints:
            raise _err(here, f"coupled joint {c['joint']!r} follows {c['follows']!r}, which is "
                       f"not one of its `joints` {list(joints)}")  # fmt: skip
    thumb = raw.get("thumb", False)
    if not isinstance(thumb, bool):
        raise _err(here, f"`thumb` must be true or false, got {thumb!r}")
    return FingerDescription(
        name=name, body=body, joints=joints, postures=tuple(postures.items()),
        tip_radius=_float(raw["tip_radius"], "tip_radius", here, low=1e-4), site=site,
        tip_pos=tip_pos, geom=geom, actuators=actuators, coupled=tuple(coupled), thumb=thumb,
        pad=_pad(raw["pad"], here) if "pad" in raw else PadDescription(),
    )  # fmt: skip


def parse_hand(data: Mapping[str, Any], base: Path, where: str) -> HandDescription:
    """A description from the parsed TOML table `data`, checked against its model.

    Args:
        data: the TOML content.
        base: directory that relative model paths start from.
        where: how messages name the description (e.g. ``"hand 'shadow'"``).

    Raises:
        HandDescriptionError: naming the missing or wrong element.
    """
    if not isinstance(data, Mapping):
        raise _err(where, "must be a TOML table")
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise _err(where, f"unknown keys {unknown}; the keys are {sorted(_TOP_KEYS)}")
    for key in ("model", "root", "fingers"):
        if key not in data:
            raise _err(where, f"`{key}` is missing")
    name = data.get("name", base.name)
    if not isinstance(name, str) or not name:
        raise _err(where, f"`name` must be a non-empty string, got {name!r}")
    extra = data.get("extra")
    model = _resolve_model(data["model"], where, base, extra if isinstance(extra, str) else None)
    root = data["root"]
    if not isinstance(root, str) or not root:
        raise _err(where, f"`root` must be a body name, got {root!r}")
    actuation = data.get("actuation", {})
    if not isinstance(actuation, dict) or set(actuation) - _ACTUATION_KEYS:
        keys = sorted(_ACTUATION_KEYS)
        raise _err(where, f"[actuation] takes the keys {keys}, got {actuation!r}")
    mode = actuation.get("mode", "model")
    if mode not in ACTUATION_MODES:
        raise _err(where, f"[actuation] `mode` must be one of {ACTUATION_MODES}, got {mode!r}")
    raw_fingers = data["fingers"]
    if not isinstance(raw_fingers, list) or not raw_fingers:
        raise _err(where, "needs at least one [[fingers]] table")
    fingers = tuple(_finger(f, k, where) for k, f in enumerate(raw_fingers))
    names = [f.name for f in fingers]
    if len(set(names)) != len(names):
        raise _err(where, f"finger names must be unique, got {names}")
    thumbs = [k for k, f in enumerate(fingers) if f.thumb]
    if not thumbs:
        raise _err(
            where, f"no finger is the thumb: the fingers {names} must start with the thumb, "
            "marked `thumb = true`",
        )  # fmt: skip
    if thumbs != [0]:
        raise _err(where, f"the thumb must be the first and only finger marked `thumb = true`, "
                   f"got {[names[k] for k in thumbs]} at positions {thumbs}")  # fmt: skip
    sweep = data.get("sweep_fingers", [])
    if not isinstance(sweep, list) or any(s not in names[1:] for s in sweep):
        raise _err(where, f"`sweep_fingers` must name fingers other than the thumb out of "
                   f"{names[1:]}, got {sweep!r}")  # fmt: skip
    hand = HandDescription(
        name=name, model=model, root=root, fingers=fingers, actuation=mode,
        kp=_float(actuation.get("kp", 3.0), "kp", where, low=1e-6),
        kv=_float(actuation.get("kv", 0.05), "kv", where, low=0.0),
        joint_margin=_float(actuation.get("joint_margin", 0.0), "joint_margin", where, low=0.0),
        sweep_fingers=tuple(names.index(s) for s in sweep),
        pad_grid=_grid(data["pad"], where) if "pad" in data else DEFAULT_PAD_GRID,
    )  # fmt: skip
    check_against_model(hand, where)
    return hand


def _chain(spec: mujoco.MjSpec, body: mujoco.MjsBody, root: str) -> list[str] | None:
    """Names of the bodies from `body` up to `root` (inclusive), or None if `root` is not an
    ancestor of `body`."""
    names = []
    while body is not None and body.name != spec.worldbody.name:
        names.append(body.name)
        if body.name == root:
            return names
        body = body.parent
    return None


def check_against_model(hand: HandDescription, where: str) -> None:
    """Check every name of `hand` against its MJCF model.

    Raises:
        HandDescriptionError: the first missing or wrong element, named.
    """
    try:
        spec = mujoco.MjSpec.from_file(str(hand.model))
    except Exception as exc:  # the MJCF parser's own message names the problem
        raise _err(where, f"cannot read {hand.model.name}: {exc}") from exc
    file = hand.model.name
    if spec.body(hand.root) is None:
        raise _err(where, f"no root body {hand.root!r} in {file}")
    degree = bool(spec.compiler.degree)
    for f in hand.fingers:
        here = f"{where}, finger {f.name!r}"
        body = spec.body(f.body)
        if body is None:
            raise _err(here, f"no body {f.body!r} in {file}")
        chain = _chain(spec, body, hand.root)
        if chain is None:
            raise _err(here, f"body {f.body!r} is not inside the root body {hand.root!r}")
        if f.site is not None:
            site = spec.site(f.site)
            if site is None:
                raise _err(here, f"no site {f.site!r} in {file}")
            if site.parent.name != f.body:
                raise _err(here, f"site {f.site!r} is on body {site.parent.name!r}, not on the "
                           f"fingertip body {f.body!r}")  # fmt: skip
        if f.geom is not None:
            geom = spec.geom(f.geom)
            if geom is None:
                raise _err(here, f"no geom {f.geom!r} in {file}")
            if geom.parent.name != f.body:
                raise _err(here, f"geom {f.geom!r} is on body {geom.parent.name!r}, not on the "
                           f"fingertip body {f.body!r}")  # fmt: skip
        on = f.pad.on
        if on is not None:
            carrier = spec.geom(on) or spec.site(on)
            if carrier is None:
                raise _err(here, f"pad: no geom or site {on!r} in {file}")
            if carrier.parent.name != f.body:
                raise _err(here, f"pad: {on!r} is on body {carrier.parent.name!r}, not on the "
                           f"fingertip body {f.body!r}")  # fmt: skip
        for j in (*f.joints, *(c.joint for c in f.coupled)):
            joint = spec.joint(j)
            if joint is None:
                raise _err(here, f"no joint {j!r} in {file}")
            if joint.parent.name not in chain or joint.parent.name == hand.root:
                raise _err(here, f"joint {j!r} (on body {joint.parent.name!r}) does not move "
                           f"the fingertip body {f.body!r} relative to the root")  # fmt: skip
            if joint.type not in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
                raise _err(here, f"joint {j!r} must be a hinge or a slide")
        for name, values in f.postures:
            for j, v in zip(f.joints, values, strict=True):
                joint = spec.joint(j)
                lo, hi = (math.radians(x) if degree else x for x in joint.range)
                if joint.limited == mujoco.mjtLimited.mjLIMITED_TRUE or lo < hi:
                    if not lo - 1e-6 <= v <= hi + 1e-6:
                        raise _err(here, f"posture `{name}`: {v} rad for joint {j!r} is outside "
                                   f"its range [{lo:.4g}, {hi:.4g}] rad")  # fmt: skip
        if hand.actuation == "model":
            if len(f.actuators) != len(f.joints):
                raise _err(here, f"actuation 'model' needs one actuator per joint in "
                           f"`actuators` ({len(f.joints)}), got {list(f.actuators)}")  # fmt: skip
            for a, j in zip(f.actuators, f.joints, strict=True):
                act = spec.actuator(a)
                if act is None:
                    raise _err(here, f"no actuator {a!r} in {file}")
                if act.trntype != mujoco.mjtTrn.mjTRN_JOINT or act.target != j:
                    raise _err(here, f"actuator {a!r} drives {act.target!r}, not joint {j!r}")


@lru_cache(maxsize=32)
def _load_file(path: str, mtime: float) -> HandDescription:
    file = Path(path)
    where = f"hand description {file.name}"
    data = read_toml(file, where, HandDescriptionError)
    if file.parent == HANDS_DIR:
        where = f"hand {file.stem!r}"
    hand = parse_hand(data, file.parent, where)
    object.__setattr__(hand, "source", file)
    return hand


def load_hand(hand: str | Path | HandDescription | None = None) -> HandDescription:
    """A hand description by shipped name (:data:`HAND_NAMES`) or TOML path, validated.

    Args:
        hand: a name, a path to a ``.toml`` file, a description (returned as is) or None
            (:data:`DEFAULT_HAND`).

    Raises:
        HandDescriptionError: unknown name (listing the shipped ones), unreadable file, or a
            description that does not match its model (naming the element).
    """
    if isinstance(hand, HandDescription):
        return hand
    if hand is None:
        hand = DEFAULT_HAND
    path = named_toml(hand, HAND_NAMES, HANDS_DIR, "hand", "hand description",
                      HandDescriptionError)  # fmt: skip
    return _load_file(str(path), path.stat().st_mtime)


__all__ = [
    "ACTUATION_MODES",
    "Coupling",
    "DEFAULT_HAND",
    "FingerDescription",
    "HAND_NAMES",
    "HandDescription",
    "HandDescriptionError",
    "DEFAULT_PAD_GRID",
    "POSTURE_NAMES",
    "PadDescription",
    "check_against_model",
    "load_hand",
    "parse_hand",
]
