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


class ChoiceError(InvalidInputError):
    """A name that is not one of the valid choices; the message builds itself, listing them
    (and the nearest, when one is close): ``"`sensing` must be one of exact, tactile, got
    'tacile' (did you mean 'tactile'?)"``.

    Args:
        argument: the argument's name.
        value: what came.
        choices: the valid names.
        also: more that is accepted, said after the choices (``"or a .toml skin file"``).
    """

    def __init__(self, argument: str, value: object, choices: object, also: str = "") -> None:
        import difflib

        names = [str(c) for c in choices]  # type: ignore[attr-defined]
        close = (
            difflib.get_close_matches(value, names, n=1, cutoff=0.6)
            if isinstance(value, str) else []
        )  # fmt: skip
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        extra = f" {also}" if also else ""
        super().__init__(
            f"`{argument}` must be one of {', '.join(names)}{extra}, got {value!r}{hint}"
        )
        self.argument, self.value, self.choices = argument, value, tuple(names)

    def __reduce__(self) -> tuple[type, tuple[str]]:
        return (InvalidInputError, (str(self),))


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
