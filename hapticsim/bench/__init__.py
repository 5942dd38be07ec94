"""The benchmark protocol (``hapticsim bench``): versioned tasks with dev and test splits,
anytime metrics of the field after every touch, results with manifests, a leaderboard.

- :mod:`hapticsim.bench.tasks`: the tasks and their seeds;
- :mod:`hapticsim.bench.runner`: a policy on a task, every metric after every touch;
- :mod:`hapticsim.bench.report`: the leaderboard (Markdown, HTML) with paired tests;
- :mod:`hapticsim.bench.record`: a policy's episodes as a Minari dataset.
"""

from hapticsim.bench.tasks import PROTOCOL, Task, get_task, task_names

__all__ = ["PROTOCOL", "Task", "get_task", "task_names"]
