"""``hapticsim bench record``: a policy's episodes of a task as a Minari dataset (offline RL).

Minari (``pip install -e ".[minari]"``) stores each episode's observations, actions, rewards and
ends; the environment is the task's ``HapticExplore-v0`` (``HapticExploreTactile-v0`` with
taxel sensing, whose pad images are stored losslessly: ``jpeg_encoding=False``), in Minari's
Arrow format; the description names the task, split, seeds and protocol. Episodes use
the task's split seeds, as ``bench run``'s do. The dataset goes where Minari keeps datasets
(``MINARI_DATASETS_PATH``, or ``root``) and reads back with ``minari.load_dataset(NAME)``.
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from hapticsim.bench.tasks import PROTOCOL, get_task
from hapticsim.errors import InvalidInputError


@contextmanager
def _datasets_path(root: str | Path | None) -> Any:
    """Minari's datasets folder set to `root` for the block (left as it is without one)."""
    if root is None:
        yield
        return
    old = os.environ.get("MINARI_DATASETS_PATH")
    os.environ["MINARI_DATASETS_PATH"] = str(Path(root).resolve())
    try:
        yield
    finally:
        if old is None:
            os.environ.pop("MINARI_DATASETS_PATH", None)
        else:
            os.environ["MINARI_DATASETS_PATH"] = old


def record_dataset(
    task: str, policy: str, episodes: int, dataset: str, split: str = "test",
    root: str | Path | None = None, progress: bool = True,
) -> dict[str, Any]:  # fmt: skip
    """Record `episodes` episodes of `policy` on `task` as the Minari dataset `dataset`.

    Args:
        task: a task name (``hapticsim bench tasks``).
        policy: a policy name or a lab's ``MODULE:ATTR`` (as ``bench run``).
        episodes: episodes from the split's first seeds.
        dataset: Minari's dataset id, ``NAMESPACE/NAME-vN`` (e.g. ``hapticsim/paper-unc-v0``).
        split: ``"dev"`` or ``"test"``.
        root: the datasets folder (default: Minari's own).
        progress: a line on stderr every 10 episodes.

    Returns:
        ``{"dataset", "path", "episodes", "steps"}``.

    Raises:
        InvalidInputError: minari missing, an unknown task or policy, a malformed dataset id or
            one that exists already.
    """
    import sys

    try:
        import minari
    except ImportError:
        raise InvalidInputError(
            'bench record needs Minari: pip install -e ".[minari]"'
        ) from None
    import warnings

    from hapticsim._version import __version__
    from hapticsim.bench.runner import checked_action, make_bench_policy
    from hapticsim.envs.haptic_explore_tactile_v0 import make_v0
    from hapticsim.envs.policies import Policy
    from hapticsim.suites.provenance import git_state

    spec = get_task(task)
    seeds = spec.seeds(split, episodes)
    if not isinstance(dataset, str) or "/" not in dataset or "-v" not in dataset:
        raise InvalidInputError(
            f"`dataset` must be a Minari id NAMESPACE/NAME-vN (e.g. hapticsim/paper-unc-v0), got "
            f"{dataset!r}"
        )
    kwargs = spec.env_kwargs()
    with _datasets_path(root):
        if dataset in minari.list_local_datasets():
            raise InvalidInputError(f"the Minari dataset {dataset!r} exists already")
        # made directly: Gymnasium cannot serialise the registered vector entry point, which
        # Minari would record with the spec; the dataset's description names the task instead
        env = make_v0(**kwargs)
        try:
            agent = make_bench_policy(policy, env, seeds[0])
            collector = minari.DataCollector(env, record_infos=False, data_format="arrow",
                                              jpeg_encoding=False)  # fmt: skip
            steps = 0
            for i, seed in enumerate(seeds):
                obs, _ = collector.reset(seed=seed)
                if isinstance(agent, Policy):
                    agent.reset(seed)
                done = False
                while not done:
                    action = checked_action(policy, agent(obs), env.action_space.shape)
                    obs, _, terminated, truncated, _ = collector.step(action)
                    done, steps = terminated or truncated, steps + 1
                if progress and ((i + 1) % 10 == 0 or i + 1 == len(seeds)):
                    print(f"hapticsim: recorded {i + 1}/{len(seeds)} episodes", file=sys.stderr,
                          flush=True)  # fmt: skip
            git = git_state() or {}
            try:
                with warnings.catch_warnings():  # its advice on optional metadata, said here
                    warnings.filterwarnings("ignore", category=UserWarning, module="minari")
                    made = collector.create_dataset(
                        dataset_id=dataset, algorithm_name=policy,
                        author="hapticsim bench record",
                        code_permalink=f"hapticsim {__version__} at {git.get('commit')}",
                        description=f"{policy} on {task} ({split} split, seeds {seeds[0]}..."
                        f"{seeds[-1]}); hapticsim's benchmark protocol {PROTOCOL}",
                    )  # fmt: skip
            except ValueError as exc:  # Minari's word on a malformed id
                raise InvalidInputError(f"Minari refused the dataset {dataset!r}: {exc}") from None
        finally:
            env.close()
        path = Path(made.spec.data_path).parent if hasattr(made, "spec") else None
    return {"dataset": dataset, "path": None if path is None else str(path),
            "episodes": len(seeds), "steps": steps}  # fmt: skip


__all__ = ["record_dataset"]
