"""A trained stable-baselines3 / sb3-contrib actor as a weight file the library runs without
torch (:class:`hapticsim.envs.learned.Actor`), and the training settings it records."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.envs.learned import RECORDED_SETTINGS, Actor, SetEncoder
from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]


def recorded_settings(env: Any, **extra: Any) -> dict[str, Any]:
    """The ``settings`` a weight file records of its training environment: the v0 settings of
    :data:`RECORDED_SETTINGS` (of its core environment, ``env.unwrapped``), then `extra`
    (e.g. ``objects``, ``reward``), then ``n_fingers``."""
    base = env.unwrapped
    settings = {k: getattr(base.config, k) for k in RECORDED_SETTINGS}
    return settings | extra | {"n_fingers": base.n_fingers}



def actor_from_sb3(model: Any, meta: dict[str, Any]) -> Actor:
    """The deterministic actor of a stable-baselines3 / sb3-contrib model (needs torch).

    Supports SAC and TQC (``policy.actor``: ``latent_pi`` then ``mu``, tanh squash), CrossQ (the
    same with BatchRenorm layers) and PPO with a Box action (``mlp_extractor.policy_net`` then
    ``action_net``; its mean action clipped to [-1, 1]). The observation must be a flat vector
    without normalisation wrappers.

    Args:
        model: the trained model.
        meta: the record to store (``env_id``, ``settings``, ``training``).

    Raises:
        InvalidInputError: a model or layer this exporter does not know.
    """
    import torch

    def walk(module: Any) -> tuple[list[str], list[Array]]:
        kinds: list[str] = []
        arrays: list[Array] = []
        for layer in module:
            name = type(layer).__name__
            if isinstance(layer, torch.nn.Linear):
                kinds.append("linear")
                arrays += [layer.weight.detach().cpu().numpy(), layer.bias.detach().cpu().numpy()]
            elif isinstance(layer, torch.nn.ReLU):
                kinds.append("relu")
            elif isinstance(layer, torch.nn.Tanh):
                kinds.append("tanh")
            elif name.startswith("BatchRenorm"):
                kinds.append("batch_renorm")
                arrays += [
                    layer.ra_mean.detach().cpu().numpy(), layer.ra_var.detach().cpu().numpy(),
                    layer.scale.detach().cpu().numpy(), layer.bias.detach().cpu().numpy(),
                ]  # fmt: skip
                meta_out["batch_renorm_eps"] = float(layer.eps)
            elif isinstance(layer, torch.nn.Flatten | torch.nn.Identity):
                continue
            else:
                raise InvalidInputError(f"the actor has a layer the exporter does not know: {name}")
        return kinds, arrays

    def encoders(extractor: Any) -> tuple[SetEncoder, ...]:
        # lab.training.sb3.TouchSetExtractor: one network per set; others: none
        if extractor is None or not hasattr(extractor, "set_nets"):
            return ()
        out = []
        for (offset, count, width), net in zip(extractor.sets, extractor.set_nets, strict=True):
            kinds, arrays = walk(net)
            out.append(SetEncoder(offset, count, width, tuple(kinds), tuple(arrays)))
        return tuple(out)

    meta_out: dict[str, Any] = dict(meta)
    policy = model.policy
    if hasattr(policy, "actor") and hasattr(policy.actor, "latent_pi"):
        actor = policy.actor
        if getattr(actor, "use_sde", False):
            raise InvalidInputError("actors with gSDE are not supported")
        sets = encoders(getattr(actor, "features_extractor", None))
        kinds, arrays = walk(actor.latent_pi)
        k2, a2 = walk([actor.mu])
        squash = "tanh"
    elif hasattr(policy, "mlp_extractor") and hasattr(policy, "action_net"):
        extractor = getattr(policy, "pi_features_extractor", None)
        sets = encoders(extractor if extractor is not None else policy.features_extractor)
        kinds, arrays = walk(policy.mlp_extractor.policy_net)
        k2, a2 = walk([policy.action_net])
        squash = "clip"
    else:
        raise InvalidInputError(f"cannot export the actor of a {type(model).__name__} model")
    return Actor(tuple(kinds + k2), tuple(arrays + a2), squash, meta_out, sets)


__all__ = ["actor_from_sb3", "recorded_settings"]
