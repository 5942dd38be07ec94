"""The one exception root of hapticsim.

Every error that hapticsim raises on purpose derives from :class:`HapticsimError`, so a caller
(and the command line, which turns it into a one-line message and exit status 2) can catch them
all at once. Messages name the argument, what was expected and what came.
"""

from __future__ import annotations


class HapticsimError(ValueError):
    """Base class of all hapticsim errors (bad input, unusable data, failed simulation)."""


class InvalidInputError(HapticsimError):
    """An argument, file or array does not have the expected type, shape, range or content."""


class SimulationError(HapticsimError):
    """The physics simulation cannot do what was asked (unreachable object, instability)."""


class ExecutionError(HapticsimError):
    """A parallel run could not finish: a worker died or the cluster could not be used."""


class WorkerDiedError(ExecutionError):
    """A worker process died while it ran a task; the task is named in the message.

    Attributes:
        task: the name of the task the worker was running.
    """

    def __init__(self, message: str, task: str) -> None:
        super().__init__(message)
        self.task = task

    def __reduce__(self) -> tuple[type, tuple[str, str]]:
        return (type(self), (str(self), self.task))


class SchedulerError(ExecutionError):
    """A Dask scheduler could not be reached, had no workers, or was lost during a run."""
