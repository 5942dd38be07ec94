"""Where the MJCF files of hapticsim live: a source checkout or an installed wheel.

The MJCF files are written by us and kept in the top-level ``models/`` directory of the
repository (STYLE layout). A wheel installs them as data files into
``<prefix>/share/hapticsim/models`` (``[tool.setuptools.data-files]`` in ``pyproject.toml``).
:func:`model_path` looks, in order, at ``$HAPTICSIM_MODELS``, the checkout next to the package, a
``models`` directory inside the package, and the ``share/hapticsim/models`` directories of the
interpreter's prefixes and of the user base.
"""

from __future__ import annotations

import os
import site
import sys
from pathlib import Path

from hapticsim.errors import ChoiceError, InvalidInputError

#: Environment variable that overrides the models directory.
MODELS_ENV: str = "HAPTICSIM_MODELS"
#: MJCF files shipped with hapticsim.
MODEL_FILES: tuple[str, ...] = ("hand.xml", "table.xml")


def _candidates() -> list[Path]:
    package = Path(__file__).resolve().parents[1]
    dirs: list[Path] = []
    if os.environ.get(MODELS_ENV):
        dirs.append(Path(os.environ[MODELS_ENV]))
    dirs.append(package.parent / "models")  # source checkout (editable install)
    dirs.append(package / "models")  # packaged inside hapticsim
    prefixes = [sys.prefix, sys.exec_prefix, sys.base_prefix]
    user_base = getattr(site, "USER_BASE", None)
    if user_base:
        prefixes.append(user_base)
    for prefix in dict.fromkeys(prefixes):
        dirs.append(Path(prefix) / "share" / "hapticsim" / "models")
    return dirs


def models_dir() -> Path:
    """The directory that holds ``hand.xml`` and ``table.xml``.

    Raises:
        InvalidInputError: no candidate directory holds the files (the message lists where it
            looked).
    """
    tried = _candidates()
    for directory in tried:
        if all((directory / name).is_file() for name in MODEL_FILES):
            return directory
    raise InvalidInputError(
        "cannot find the hapticsim MJCF models (hand.xml, table.xml); looked in "
        + ", ".join(str(d) for d in tried)
        + f"; set ${MODELS_ENV} to the models directory"
    )


def model_path(name: str) -> Path:
    """The path of a shipped MJCF file, e.g. ``model_path("hand.xml")``.

    Raises:
        InvalidInputError: an unknown name (the message lists the files) or missing files.
    """
    if name not in MODEL_FILES:
        raise ChoiceError("name", name, MODEL_FILES)
    return models_dir() / name


__all__ = ["MODELS_ENV", "MODEL_FILES", "model_path", "models_dir"]
