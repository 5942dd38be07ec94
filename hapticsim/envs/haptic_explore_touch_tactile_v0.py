"""``hapticsim/HapticExploreTouchTactile-v0``: the touch-history task felt through taxel pads,
each touch's pad image in its set element (:class:`HapticExploreTouchTactileEnv`, a wrapper of
the tactile core :class:`~hapticsim.envs.haptic_explore_tactile_v0.HapticExploreTactileEnv`)."""

from __future__ import annotations

from typing import Any

from hapticsim.envs.haptic_explore_compact_v0 import HapticExploreV1Config
from hapticsim.envs.haptic_explore_tactile_v0 import HapticExploreTactileEnv
from hapticsim.envs.haptic_explore_touch_v0 import TAXEL_GRID, HapticExploreTouchEnv
from hapticsim.errors import InvalidInputError


class HapticExploreTouchTactileEnv(HapticExploreTouchEnv):
    """:class:`HapticExploreTouchEnv`'s task felt through taxel pads (``sensing="tactile"``),
    each touch's pad image in its set element.

    Contacts are estimated from the pads, as in ``hapticsim/HapticExploreTactile-v0`` (the core
    it wraps: ``skin`` and the other tactile settings as there); the observation is the
    touch history of :class:`TouchObserver` with ``taxels=True``.

    ## Observation space

    ``Box(-10, 10, (1569,), float32)``: 17 head entries, 64 contacts x 7, 16 touches x 69
    (approach, contacts it brought / 10, the pad that felt most pooled to 8 x 8 blocks over
    the largest, present). Sets: :data:`TACTILE_SETS`. No ground truth.

    ## Version history

    - v0: initial version.
    """

    taxels = True

    def __init__(self, render_mode: str | None = None, config: Any = None, **kwargs: Any) -> None:
        if config is not None and kwargs:
            raise InvalidInputError("give either `config` or keyword arguments, not both")
        if config is None:
            kwargs.setdefault("sensing", "tactile")
            config = HapticExploreV1Config.from_kwargs(**kwargs)
        if not isinstance(config, HapticExploreV1Config):
            raise InvalidInputError(
                f"`config` must be a HapticExploreV1Config, got {type(config).__name__}"
            )
        core = HapticExploreTactileEnv(render_mode=render_mode, config=config.core)
        super().__init__(core, render_mode=render_mode, config=config)
        _, rows, cols = core.taxel_shape
        if rows < TAXEL_GRID or cols < TAXEL_GRID:
            raise InvalidInputError(
                f"the pads have {rows} x {cols} taxels; this observation pools them to "
                f"{TAXEL_GRID} x {TAXEL_GRID} blocks and needs at least that many (a skin of "
                "finer pitch)"
            )


__all__ = ["HapticExploreTouchTactileEnv"]
