"""The ``hapticsim`` command line (SPEC §6): thin — parse, call, print.

Where a command prints JSON, stdout carries only that JSON; progress and logs go to stderr.
Any :class:`~hapticsim.errors.HapticsimError` (and a bad command line) ends with one line on
stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

from hapticsim.errors import HapticsimError

EXIT_BAD_INPUT = 2


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose errors are one line on stderr, exit status 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def _seed(text: str) -> int:
    """argparse type of ``--seed``: an int >= 0 (what ``numpy.random.default_rng`` accepts)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {text!r}")
    return value


def _print_json(data: Any) -> None:
    sys.stdout.write(json.dumps(data, indent=2) + "\n")
    sys.stdout.flush()


# ----------------------------------------------------------------------------- commands
def _cmd_synth(args: argparse.Namespace) -> int:
    from hapticsim.data import io
    from hapticsim.data.bodies import resolve_body
    from hapticsim.data.synthetic import paper_dataset

    # Check both outputs first so that bad input never leaves one of them written.
    io.check_output_path(args.out, io.CONTACT_SUFFIXES)
    if args.truth_out:
        io.check_output_path(args.truth_out)
    truth = resolve_body(args.body)
    contacts = paper_dataset(truth, noise=args.noise, rng=args.seed, count=args.count)
    io.write_contacts(args.out, contacts)
    if args.truth_out:
        truth.to_json(args.truth_out)
    _print_json({"contacts": str(args.out), "count": len(contacts), "truth": truth.to_dict()})
    return 0


def _cmd_score(args: argparse.Namespace) -> int:
    from hapticsim.geometry import Superquadric
    from hapticsim.metrics import score

    estimate = Superquadric.from_json(args.estimate)
    truth = Superquadric.from_json(args.truth)
    _print_json(score(estimate, truth, rng=args.seed).to_dict())
    return 0


def _cmd_fit(args: argparse.Namespace) -> int:
    from hapticsim.data.io import read_contacts, write_json
    from hapticsim.fitting import fit

    contacts = read_contacts(args.contacts)
    result = fit(
        contacts.points,
        contacts.normals,
        method=args.method,
        budget=args.budget,
        rng=args.seed,
    )
    out = result.to_dict()
    if args.out:
        write_json(args.out, out)
    _print_json(out)
    return 0


def _cmd_explore(args: argparse.Namespace) -> int:
    from hapticsim.experiments.explore import explore

    summary = explore(
        object_name=args.object,
        strategy=args.strategy,
        noise=args.noise,
        method=args.method,
        seed=args.seed,
        out_dir=args.out,
        render=args.render,
        progress=not args.quiet,
        count=args.count,
    )
    if not summary["complete"]:
        sys.stderr.write(
            f"hapticsim explore: warning: gathered {summary['contacts']} of "
            f"{summary['requested']} contacts: {summary['stop_reason']}\n"
        )
    _print_json(summary)
    return 0


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from hapticsim.experiments.reproduce import reproduce

    summary = reproduce(
        args.which,
        out_dir=args.out,
        runs=args.runs,
        seed=args.seed,
        workers=args.workers,
        results=args.results,
        figures_dir=args.figures_dir,
        progress=not args.quiet,
    )
    _print_json(summary)
    return 0


# ----------------------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``hapticsim`` (exposed for tests and docs)."""
    from hapticsim.data.bodies import BODY_NAMES
    from hapticsim.fitting.methods import DEFAULT_BUDGET, METHODS

    parser = _Parser(
        prog="hapticsim",
        description="Haptic exploration testbed: superquadric recovery from contacts.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("synth", help="synthetic contact data of a body (paper Section III-A)")
    p.add_argument("body", help=f"one of {', '.join(BODY_NAMES)}, or a superquadric JSON file")
    p.add_argument("--noise", type=float, default=0.1, help="relative noise sigma_N (default 0.1)")
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument("--count", type=int, default=150, help="number of contacts (default 150)")
    p.add_argument("--out", default="contacts.npz", help=".npz or .csv (default contacts.npz)")
    p.add_argument("--truth-out", default=None, help="also write the true superquadric JSON")
    p.set_defaults(func=_cmd_synth)

    p = sub.add_parser("score", help="quality measures of an estimate against the truth")
    p.add_argument("estimate", help="superquadric or fit-result JSON")
    p.add_argument("truth", help="superquadric JSON")
    p.add_argument("--seed", type=_seed, default=0, help="seed of the volume sampling")
    p.set_defaults(func=_cmd_score)

    p = sub.add_parser("fit", help="fit a superquadric to a contacts file")
    p.add_argument("contacts", help=".npz or .csv contacts file (SPEC §6)")
    p.add_argument("--method", choices=METHODS, default="nH")
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument(
        "--budget", type=int, default=None, help=f"EOF evaluations (default {DEFAULT_BUDGET})"
    )
    p.add_argument("--out", default=None, help="also write the result JSON here")
    p.set_defaults(func=_cmd_fit)

    p = sub.add_parser("explore", help="simulated haptic exploration, fit and score")
    p.add_argument("--object", default="cube", help="object name (default cube)")
    p.add_argument("--strategy", default="paper", help="exploration strategy (default paper)")
    p.add_argument("--noise", type=float, default=0.0, help="sensor noise sigma_N (default 0)")
    p.add_argument("--method", choices=METHODS, default="nH")
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument(
        "--out", default=None, help="output directory (default runs/OBJECT-STRATEGY-seedN)"
    )
    p.add_argument("--count", type=int, default=150, help="contacts to gather (default 150)")
    p.add_argument("--render", action="store_true", help="also render the scene (MUJOCO_GL=egl)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_explore)

    p = sub.add_parser("reproduce", help="regenerate the paper's Fig. 4 / Fig. 5")
    p.add_argument("which", choices=("fig4", "fig5", "all"))
    p.add_argument("--out", default="runs/reproduce", help="output directory")
    p.add_argument("--runs", type=int, default=10, help="runs (data sets) per setting (default 10)")
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    p.add_argument(
        "--results", default=None, help="also write the Markdown report here (e.g. RESULTS.md)"
    )
    p.add_argument(
        "--figures-dir", default=None, help="pictures of the report (default: docs/figures)"
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_reproduce)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``hapticsim`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except HapticsimError as exc:
        message = " ".join(str(exc).split())
        sys.stderr.write(f"hapticsim {args.command}: error: {message}\n")
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        sys.stderr.write("hapticsim: interrupted\n")
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
