"""stable-baselines3 glue (needs the ``rl`` extra): a permutation-invariant encoder of the touch
observation, and hapticsim's native vector environment as an SB3 ``VecEnv``.

- :class:`TouchSetExtractor`: the features extractor of ``hapticsim/HapticExploreTouch-v0``'s
  observation (:mod:`hapticsim.envs.haptic_explore_touch_v0`): a small network applied to every
  present element of each set (contacts, touches), pooled by maximum and mean, beside the
  observation's head. :func:`hapticsim.envs.learned.actor_from_sb3` exports it with the actor,
  and :class:`hapticsim.envs.learned.Actor` runs it in numpy.
- :class:`NativeVecEnv`: :class:`~hapticsim.envs.vector.HapticVectorEnv` (N environments in one
  worker process per core) behind SB3's ``VecEnv`` interface, episodes reset in the step that
  ends them, the last observation in ``info["terminal_observation"]``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import torch
from gymnasium import spaces
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from hapticsim.envs.vector import HapticVectorEnv
from hapticsim.errors import InvalidInputError

#: Info entries passed on per environment (the rest of the batched info is dropped).
INFO_KEYS: tuple[str, ...] = ("epsilon", "alpha", "beta", "iou", "coverage_gap")


class TouchSetExtractor(BaseFeaturesExtractor):
    """Head entries and, per set, max- and mean-pooled features of its present elements.

    Args:
        observation_space: a flat ``Box`` whose tail holds the sets.
        sets: (offset, count, width) per set, following one another to the observation's end
            (default: ``hapticsim/HapticExploreTouch-v0``'s :data:`~hapticsim.envs.
            haptic_explore_touch_v0.SETS`); an element's last number is 1 where it is present.
        hidden: widths of every set's per-element network (ReLU after each layer).
    """

    def __init__(
        self,
        observation_space: spaces.Box,
        sets: tuple[tuple[int, int, int], ...] | None = None,
        hidden: tuple[int, ...] = (64, 64),
    ) -> None:
        if sets is None:
            from hapticsim.envs.haptic_explore_touch_v0 import SETS

            sets = SETS
        sets = tuple(tuple(int(v) for v in s) for s in sets)
        end = sets[-1][0] + sets[-1][1] * sets[-1][2]
        if observation_space.shape != (end,):
            raise InvalidInputError(
                f"the sets end at {end}; the observation space has shape {observation_space.shape}"
            )
        head = sets[0][0]
        super().__init__(observation_space, head + 2 * hidden[-1] * len(sets))
        self.sets = sets
        self.head = head
        nets = []
        for _, _, width in sets:
            layers: list[torch.nn.Module] = []
            n_in = width - 1
            for n_out in hidden:
                layers += [torch.nn.Linear(n_in, n_out), torch.nn.ReLU()]
                n_in = n_out
            nets.append(torch.nn.Sequential(*layers))
        self.set_nets = torch.nn.ModuleList(nets)

    def forward(self, obs: torch.Tensor) -> torch.Tensor:  # noqa: D102
        parts = [obs[:, : self.head]]
        for (offset, count, width), net in zip(self.sets, self.set_nets, strict=True):
            e = obs[:, offset : offset + count * width].reshape(-1, count, width)
            present = e[:, :, -1:] > 0.5
            h = net(e[:, :, :-1])
            n = present.sum(dim=1)
            top = torch.where(present, h, torch.full_like(h, -torch.inf)).amax(dim=1)
            top = torch.where(n > 0, top, torch.zeros_like(top))
            mean = torch.where(present, h, torch.zeros_like(h)).sum(dim=1) / n.clamp(min=1)
            parts += [top, mean]
        return torch.cat(parts, dim=1)


class NativeVecEnv(VecEnv):
    """:class:`~hapticsim.envs.vector.HapticVectorEnv` as a stable-baselines3 ``VecEnv``.

    Args:
        env_id: a hapticsim environment id with a flat observation (``HapticExploreCompact-v0``,
            ``HapticExploreTouch-v0``).
        num_envs: environments.
        workers: worker processes (default one per core).
        **kwargs: the environments' settings.
    """

    def __init__(
        self, env_id: str, num_envs: int, workers: int | None = None, **kwargs: Any
    ) -> None:
        self.venv = HapticVectorEnv(
            env_id, num_envs, workers=workers, autoreset_mode="same_step", **kwargs
        )
        super().__init__(
            num_envs, self.venv.single_observation_space, self.venv.single_action_space
        )
        self._actions: np.ndarray | None = None

    def reset(self) -> np.ndarray:  # noqa: D102
        obs, _ = self.venv.reset(seed=list(self._seeds))  # None: an environment's own stream
        self._reset_seeds()
        return obs

    def step_async(self, actions: np.ndarray) -> None:  # noqa: D102
        self._actions = np.asarray(actions, np.float32)

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:  # noqa: D102
        if self._actions is None:
            raise InvalidInputError("step_async must come before step_wait")
        obs, rewards, terminated, truncated, info = self.venv.step(self._actions)
        self._actions = None
        dones = terminated | truncated
        final = info.get("final_info", {})
        infos: list[dict[str, Any]] = []
        for i in range(self.num_envs):
            source = final if dones[i] else info
            entry = {k: source[k][i] for k in INFO_KEYS if k in source and source[f"_{k}"][i]}
            if dones[i]:
                entry["terminal_observation"] = info["final_obs"][i]
                entry["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            infos.append(entry)
        return obs, rewards.astype(np.float32), dones, infos

    def close(self) -> None:  # noqa: D102
        self.venv.close()

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:  # noqa: D102
        values = self.venv.get_attr(attr_name)
        return [values[i] for i in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:  # noqa: D102
        if indices is not None:
            raise InvalidInputError("set_attr sets every environment's attribute (indices=None)")
        self.venv.set_attr(attr_name, value)

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kwargs: Any) -> list:  # noqa: D102
        values = self.venv.call(method_name, *args, **kwargs)
        return [values[i] for i in self._get_indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:  # noqa: D102
        return [False for _ in self._get_indices(indices)]
