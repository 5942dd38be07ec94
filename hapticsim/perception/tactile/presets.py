"""Named skins (``hapticsim/perception/tactile/skins/*.toml``) and skin files.

A skin file is a small TOML table; the shipped presets use the same format::

    name = "myskin"
    description = "one line"
    source = "where the numbers come from"
    pitch = 0.002            # [m], optional: the sensor's own taxel pitch

    [skin]                   # the elastic layer (hapticsim.perception.tactile.skin.SkinModel)
    modulus = 2.0e5          # Young's modulus [Pa]
    thickness = 0.002        # [m]
    poisson = 0.49           # optional: the layer law with this Poisson's ratio (needs the
                             # `fem` extra); without it the Winkler law

    [sensor]                 # the electronics (SensorModel); every key optional
    noise = 500.0            # [Pa] per taxel and reading
    full_scale = 2.0e5       # [Pa]
    bits = 12
    gain_spread = 0.02       # relative std of the per-taxel gains
    dead_fraction = 0.0
    blur = 1.0               # [taxels]
    threshold = 2000.0       # [Pa]

Shipped (:data:`SKIN_NAMES`): ``ideal`` (no sensor effects), ``vision`` (a high-resolution
vision-based pad), ``capacitive`` (a coarse capacitive skin), ``elastomer`` (the ideal
sensor on a near-incompressible layer read with the layer's contact law) and ``gelsight_mini``
(the GelSight Mini's gel, its layer calibrated against the sensor's measured force-indentation
curve; docs/tactile/calibration/README.md); the last two need the ``fem`` extra. Each file
names its sources and which of its numbers are assumed.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Any

from hapticsim._files import named_toml, read_toml
from hapticsim.errors import InvalidInputError
from hapticsim.perception.tactile.skin import SensorModel, SkinModel, SkinPreset

#: Names of the shipped presets.
SKIN_NAMES: tuple[str, ...] = ("ideal", "vision", "capacitive", "elastomer", "gelsight_mini")
#: The preset used when none is named.
DEFAULT_SKIN: str = "ideal"
#: Directory of the shipped presets.
SKINS_DIR: Path = Path(__file__).resolve().parent / "skins"

_TOP_KEYS = {"name", "description", "source", "pitch", "skin", "sensor"}
_SKIN_KEYS = {"modulus", "thickness", "poisson"}
_SENSOR_KEYS = {"noise", "full_scale", "bits", "gain_spread", "dead_fraction", "blur", "threshold"}


class SkinError(InvalidInputError):
    """A skin that cannot be used; the message names the file and the key."""


def _check_keys(table: Any, allowed: set[str], where: str) -> dict[str, Any]:
    if not isinstance(table, dict):
        raise SkinError(f"{where} must be a table, got {table!r}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise SkinError(f"{where}: unknown key(s) {unknown}; the keys are {sorted(allowed)}")
    for key, value in table.items():
        if key in ("name", "description", "source"):
            if not isinstance(value, str):
                raise SkinError(f"{where}: `{key}` must be a string, got {value!r}")
        elif key not in ("skin", "sensor") and (
            isinstance(value, bool) or not isinstance(value, (int, float))
        ):
            raise SkinError(f"{where}: `{key}` must be a number, got {value!r}")
    return table


def parse_skin(data: Any, where: str) -> SkinPreset:
    """A preset from a parsed skin table (module docstring).

    Raises:
        SkinError: an unknown key, a value of the wrong type or out of its domain (named).
    """
    top = _check_keys(data, _TOP_KEYS, where)
    skin = _check_keys(top.get("skin", {}), _SKIN_KEYS, f"{where} [skin]")
    sensor = _check_keys(top.get("sensor", {}), _SENSOR_KEYS, f"{where} [sensor]")
    if "bits" in sensor:
        bits = sensor["bits"]
        if not float(bits).is_integer():
            raise SkinError(f"{where} [sensor]: `bits` must be an integer, got {bits!r}")
        sensor = {**sensor, "bits": int(bits)}
    try:
        return SkinPreset(
            name=top.get("name", where), skin=SkinModel(**skin), sensor=SensorModel(**sensor),
            pitch=top.get("pitch"), description=top.get("description", ""),
            source=top.get("source", ""),
        )  # fmt: skip
    except InvalidInputError as exc:
        raise SkinError(f"{where}: {exc}") from exc


@lru_cache(maxsize=32)
def _load_file(path: str, mtime: float) -> SkinPreset:
    file = Path(path)
    where = f"skin file {file.name}"
    data = read_toml(file, where, SkinError)
    if file.parent == SKINS_DIR:
        where = f"skin {file.stem!r}"
    return parse_skin(data, where)


def load_skin(skin: str | Path | SkinPreset | None = None) -> SkinPreset:
    """A skin by preset name (:data:`SKIN_NAMES`) or ``.toml`` path.

    Args:
        skin: a name, a path, a preset (returned as is) or None (:data:`DEFAULT_SKIN`).

    Raises:
        SkinError: an unknown name (listing the presets, with the nearest as a suggestion), a
            missing or unreadable file, or a file that does not parse (naming the key).
    """
    if isinstance(skin, SkinPreset):
        return skin
    if skin is None:
        skin = DEFAULT_SKIN
    path = named_toml(skin, SKIN_NAMES, SKINS_DIR, "skin", "skin file", SkinError)
    return _load_file(str(path), path.stat().st_mtime)


__all__ = ["DEFAULT_SKIN", "SKINS_DIR", "SKIN_NAMES", "SkinError", "load_skin", "parse_skin"]
