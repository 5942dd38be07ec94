"""One hypothesis strategy per ``hapticsim`` command: fuzzed files plus fuzzed argument values.

A :class:`Case` is an argument list and the files to create before running it. Each command's
strategy mostly draws valid values (so that runs get deep into the program) and sometimes bad
ones (so that every check is met); :data:`COMMANDS` maps command names to strategies, and
:func:`command_names` lists the commands the parser has, so a new command without a strategy
here is noticed (:func:`tests.fuzz.test_fuzz_cli.test_every_command_is_fuzzed`).

``cost`` names the expensive commands, whose valid runs are kept small (few contacts, one run)
so that hundreds of invocations take minutes.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass, field

from hypothesis import strategies as st

from hapticsim.data.bodies import BODY_NAMES
from hapticsim.fitting.methods import FIT_METHODS, METHODS
from tests.fuzz.inputs import (
    EXISTING,
    JUNK_TOKENS,
    FileSpec,
    choice,
    contacts_files,
    floats,
    ints,
    json_files,
    json_values,
    mostly,
    mutated_bytes,
    out_paths,
)

#: Directory every case's work directory has (an existing directory for outputs to hit).
EXISTING_DIR = EXISTING


@dataclass(frozen=True)
class Case:
    """An invocation: ``hapticsim *argv`` after creating `files` in a fresh directory."""

    argv: tuple[str, ...]
    files: tuple[FileSpec, ...] = field(default=())


def _options(draw: st.DrawFn, options: dict[str, st.SearchStrategy[str]]) -> list[str]:
    """Some of `options` (each with probability 1/2), values drawn, in a random order."""
    argv: list[str] = []
    names = [name for name in options if draw(st.booleans())]  # each with probability 1/2
    for name in draw(st.permutations(names)):
        argv += [name, draw(options[name])]
    if draw(st.integers(0, 19)) == 0:  # an unknown or malformed option now and then
        argv.append(draw(st.sampled_from(JUNK_TOKENS)))
    return argv


@st.composite
def fit_cases(draw: st.DrawFn) -> Case:
    contacts = draw(contacts_files())
    argv = ["fit", contacts.name] + _options(
        draw,
        {
            "--method": choice(FIT_METHODS, ("GA", "nh ", "")),
            "--seed": ints((0, 2**32)),
            "--budget": ints((1, 3000)),
            "--out": out_paths("fit", ".json"),
            "--noise": floats((0.0, 0.2)),
        },
    )
    if draw(st.integers(0, 4)) == 0:
        argv.append("--free-space")
    return Case(tuple(argv), (contacts,))


@st.composite
def score_cases(draw: st.DrawFn) -> Case:
    estimate = draw(json_files("estimate"))
    truth = draw(st.one_of(json_files("truth"), json_files("truth"), st.just(estimate)))
    argv = ["score", estimate.name, truth.name] + _options(draw, {"--seed": ints((0, 2**32))})
    return Case(tuple(argv), (estimate, truth) if truth is not estimate else (estimate,))


@st.composite
def synth_cases(draw: st.DrawFn) -> Case:
    body = draw(st.one_of(st.sampled_from(BODY_NAMES + ("sphere", "")), json_files("body")))
    files = (body,) if isinstance(body, FileSpec) else ()
    name = body.name if isinstance(body, FileSpec) else body
    argv = ["synth", name] + _options(
        draw,
        {
            "--noise": floats((0.0, 1.0)),
            "--seed": ints((0, 2**32)),
            "--count": ints((13, 400)),
            "--out": st.one_of(out_paths("contacts", ".npz"), out_paths("contacts", ".csv")),
            "--truth-out": out_paths("truth", ".json"),
        },
    )
    return Case(tuple(argv), files)


@st.composite
def explore_cases(draw: st.DrawFn) -> Case:
    from hapticsim.sim.strategies import strategy_names

    argv = ["explore", "--out", draw(out_paths("run", ""))]
    if draw(st.booleans()):
        argv.append("--quiet")
    argv += ["--count", draw(st.one_of(ints((20, 30)), st.sampled_from(["19"])))]
    argv += _options(
        draw,
        {
            "--object": choice(BODY_NAMES, ("sphere", "random", "")),
            "--strategy": choice(strategy_names(), ("wander",)),
            "--noise": floats((0.0, 0.3)),
            "--method": choice(METHODS, ("GA",)),
            "--seed": ints((0, 2**32)),
        },
    )
    if draw(st.integers(0, 9)) == 0:
        argv.append("--render")
    return Case(tuple(argv))


@st.composite
def reproduce_cases(draw: st.DrawFn) -> Case:
    # valid sweeps are costly (fig4 with one run: 16 fits, ~7 s): most cases break one value
    which = draw(st.sampled_from(["fig4", "fig4", "fig5", "all", "fig6", ""]))
    runs = draw(st.sampled_from(["1", "1", "0", "-1", "1.5", "x", "100001", str(2**70)]))
    argv = ["reproduce", which, "--quiet", "--runs", runs, "--out", draw(out_paths("rep", ""))]
    argv += _options(
        draw,
        {
            "--seed": ints((0, 2**32)),
            "--workers": st.sampled_from(["1", "2", "0", "-2", "two", "1.0"]),
            "--results": out_paths("RESULTS", ".md"),
            "--figures-dir": out_paths("figures", ""),
        },
    )
    expensive = which in ("fig5", "all") and runs == "1"
    if expensive and draw(st.integers(0, 3)) != 0:
        argv += ["--workers", "0"]  # keep most fig5 sweeps to their argument check
    return Case(tuple(argv))


_BASE_RESULTS: dict[str, bytes] = {}


def base_results() -> bytes:
    """A small, real ``suite run`` results file (two fit-v1 cases), made once per process."""
    if "fit" not in _BASE_RESULTS:
        from hapticsim.suites.runner import results_text, run_suite

        results = run_suite("fit-v1", cases="cube/nLS/noise=0.05/run=[01]", workers=1,
                            progress=False)  # fmt: skip
        _BASE_RESULTS["fit"] = results_text(results).encode()
    return _BASE_RESULTS["fit"]


@st.composite
def results_files(draw: st.DrawFn, stem: str) -> FileSpec:
    """A suite results file: the real one, one with JSON values replaced, or broken bytes."""
    kind = draw(mostly(st.just("json"), st.sampled_from(["dir", "missing", "values"])))
    if kind == "dir":
        return FileSpec(f"{stem}.json", directory=True)
    if kind == "missing":
        return FileSpec(f"{stem}.json")
    data = base_results()
    if kind == "values" or draw(st.booleans()):
        value = json.loads(data)
        for _ in range(draw(st.integers(1, 3))):
            path = draw(st.sampled_from(_RESULT_PATHS))
            node = value
            for key in path[:-1]:
                node = node[key] if isinstance(node, dict) and key in node else None
                if node is None:
                    break
            if isinstance(node, dict):
                if draw(st.booleans()):
                    node.pop(path[-1], None)
                else:
                    node[path[-1]] = draw(json_values)
        data = json.dumps(value, allow_nan=True).encode()
    return FileSpec(f"{stem}.json", draw(mutated_bytes(data)))


#: Places in a results file the fuzzer replaces or removes.
_RESULT_PATHS: tuple[tuple[str, ...], ...] = (
    ("format",), ("format_version",), ("suite",), ("suite", "id"), ("suite", "version"),
    ("cases",), ("summary",), ("groups",), ("selection",),
)  # fmt: skip


@st.composite
def suite_cases(draw: st.DrawFn) -> Case:
    what = draw(st.sampled_from(["list", "run", "run", "compare", "compare", ""]))
    if what == "list":
        return Case(("suite", "list", *_options(draw, {})))
    if what == "compare":
        baseline, results = draw(results_files("baseline")), draw(results_files("results"))
        argv = ["suite", "compare", baseline.name, results.name] + _options(
            draw, {"--tolerance": floats((0.0, 0.1)), "--alpha": floats((0.001, 0.5))}
        )
        argv += [flag for flag in ("--json", "--changed") if draw(st.booleans())]
        files = (baseline,) if results.name == baseline.name else (baseline, results)
        return Case(tuple(argv), files)
    if what == "":
        return Case(("suite", *draw(st.lists(st.sampled_from(JUNK_TOKENS), max_size=2))))
    # run: a cheap selection of a shipped suite, another name, or a (mutated) suite file
    name = draw(st.sampled_from(["fit-v1", "fit-v1", "fit-v1", "explore-v1", "fit-v9", "file"]))
    files: tuple[FileSpec, ...] = ()
    if name == "file":
        from hapticsim.suites.suite import load_suite

        text = load_suite("fit-v1").path.read_bytes()
        files = (FileSpec("mine.toml", draw(mutated_bytes(text))),)
        name = "mine.toml"
    pattern = {"fit-v1": "cube/nH/noise=0.05/run=0", "explore-v1": "cube/patch/noise=0/run=0"}
    argv = ["suite", "run", name, "--quiet", "--out", draw(out_paths("results", ".json"))]
    argv += ["--cases", draw(mostly(st.just(pattern.get(name, "*/nH/noise=0/run=0")),
                                    st.sampled_from(["*", "[", "nothing/*", ""])))]  # fmt: skip
    argv += _options(
        draw,
        {
            "--workers": st.sampled_from(["1", "1", "2", "0", "x"]),
            "--fitter": st.sampled_from(
                ["hapticsim.fitting:fit", "math:sqrt", "nope:fit", "hapticsim", "json:loads"]
            ),  # fmt: skip
            "--policy": st.sampled_from(["hapticsim.envs.policies:RandomPolicy", "nope:P"]),
        },
    )
    if draw(st.integers(0, 9)) == 0:  # an unreachable Dask scheduler, found out quickly
        argv = [a for a in argv if a != "--workers"]
        argv += ["--scheduler", "tcp://127.0.0.1:9", "--scheduler-timeout", "0.5"]
    return Case(tuple(argv), files)


@st.composite
def generic_cases(draw: st.DrawFn, command: str) -> Case:
    """Junk tokens after a command this module has no strategy for yet."""
    tokens = draw(st.lists(st.sampled_from(JUNK_TOKENS + ("list", "run", "1")), max_size=4))
    return Case((command, *tokens))


#: Strategy of each command's cases.
COMMANDS: dict[str, st.SearchStrategy[Case]] = {
    "fit": fit_cases(),
    "score": score_cases(),
    "synth": synth_cases(),
    "explore": explore_cases(),
    "reproduce": reproduce_cases(),
    "suite": suite_cases(),
}


def command_names() -> tuple[str, ...]:
    """The subcommands of ``hapticsim`` (from its parser)."""
    from hapticsim.cli import build_parser

    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            return tuple(action.choices)
    return ()


def cases(commands: tuple[str, ...] | None = None) -> st.SearchStrategy[Case]:
    """Cases of the given commands (default: all of the parser's), chosen uniformly."""
    names = commands or command_names()
    return st.one_of(*(COMMANDS.get(n, generic_cases(n)) for n in names))


__all__ = ["COMMANDS", "Case", "EXISTING_DIR", "cases", "command_names"]
