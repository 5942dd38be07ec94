"""``hapticsim suite ...`` and ``hapticsim policies ...``: their parsers and commands (thin, as
the rest of :mod:`hapticsim.cli`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from hapticsim._cli_common import _Parser, _positive_int, _print_json, _seed
from hapticsim.envs.evaluation import evaluate_policy
from hapticsim.errors import InvalidInputError


def _cmd_suite_list(args: argparse.Namespace) -> int:
    from hapticsim.suites import list_suites

    _print_json([s.summary() for s in list_suites()])
    return 0


def _cmd_suite_run(args: argparse.Namespace) -> int:
    from hapticsim.suites.runner import run_suite, summary_line

    results = run_suite(
        args.name, args.out, workers=args.workers, scheduler=args.scheduler,
        timeout=args.scheduler_timeout, fitter=args.fitter, policy=args.policy,
        cases=args.cases, progress=not args.quiet, command=["hapticsim", *args.argv],
    )  # fmt: skip
    failed = [c for c in results["cases"] if c["status"] != "ok"]
    if failed:
        sys.stderr.write(
            f"hapticsim suite run: {len(failed)} of {len(results['cases'])} cases failed "
            f"(first: {failed[0]['id']}: {failed[0]['error']})\n"
        )
    _print_json({**summary_line(results), "out": str(args.out)})
    return 0


def _cmd_suite_compare(args: argparse.Namespace) -> int:
    from hapticsim.suites import compare_results

    comparison = compare_results(args.baseline, args.results, args.tolerance, args.alpha)
    if args.json:
        _print_json(comparison.to_dict())
    else:
        sys.stdout.write(comparison.table(all_groups=not args.changed) + "\n")
    return comparison.exit_code


def _cmd_suite_report(args: argparse.Namespace) -> int:
    from hapticsim.suites.html_report import write_report

    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InvalidInputError(f"--out {out} exists and is not a directory")
    if not out.parent.is_dir():
        raise InvalidInputError(f"cannot write {out}: directory {out.parent} does not exist")
    index = write_report(args.results, out, args.baseline, args.tolerance, args.alpha)
    _print_json({"report": str(index), "results": args.results, "baseline": args.baseline})
    return 0


def add_suite_parser(sub: Any) -> None:
    """``hapticsim suite list | run | compare`` (regression suites, SPEC §6)."""
    suite = sub.add_parser(
        "suite", help="regression suites of reconstruction quality: list, run, compare"
    )
    cmds = suite.add_subparsers(dest="suite_command", required=True, parser_class=_Parser)
    p = cmds.add_parser("list", help="the shipped suites: names, versions, case counts (JSON)")
    p.set_defaults(func=_cmd_suite_list)

    p = cmds.add_parser("run", help="run a suite's cases and write the results JSON")
    p.add_argument("name", help="a suite (hapticsim suite list), or a suite .toml file")
    p.add_argument("--out", required=True, help="results JSON (written atomically)")
    engine = p.add_mutually_exclusive_group()
    engine.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    engine.add_argument(
        "--scheduler", default=None, help="run on a Dask cluster: tcp://host:port or local:N"
    )
    p.add_argument(
        "--scheduler-timeout", type=float, default=10.0, metavar="S",
        help="seconds to wait for the Dask scheduler (default 10)",
    )  # fmt: skip
    p.add_argument("--fitter", default=None, help="MODULE:FUNCTION, fit(points, normals)")
    p.add_argument("--policy", default=None, help="MODULE:CLASS with the baseline policies' API")
    p.add_argument("--cases", default=None, help="only cases whose id matches, e.g. '*/nH/*'")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_suite_run)

    p = cmds.add_parser(
        "compare", help="pair two runs' cases; exit 0 no regression, 1 regression, 2 bad input"
    )
    p.add_argument("baseline", help="results JSON of the baseline")
    p.add_argument("results", help="results JSON to check")
    p.add_argument(
        "--tolerance", type=float, default=0.01, help="harmless rise of a group's mean epsilon"
    )
    p.add_argument("--alpha", type=float, default=0.01, help="level of the paired Wilcoxon test")
    p.add_argument("--changed", action="store_true", help="list only groups that changed")
    p.add_argument("--json", action="store_true", help="print the comparison as JSON")
    p.set_defaults(func=_cmd_suite_compare)

    p = cmds.add_parser(
        "report", help="an HTML page of a results file (against a baseline): tables and plots"
    )
    p.add_argument("results", help="results JSON (hapticsim suite run --out)")
    p.add_argument("--baseline", default=None, help="results JSON to compare against")
    p.add_argument("--out", required=True, help="directory for index.html and its pictures")
    p.add_argument(
        "--tolerance", type=float, default=None, help="harmless rise of a group's mean epsilon"
    )
    p.add_argument("--alpha", type=float, default=None, help="level of the paired Wilcoxon test")
    p.set_defaults(func=_cmd_suite_report)


def _cmd_policies_evaluate(args: argparse.Namespace) -> int:
    if args.skin is not None and args.sensing != "tactile":
        raise InvalidInputError("--skin is for --sensing tactile")
    result = evaluate_policy(
        args.policy, backend=args.backend, objects=args.objects, episodes=args.episodes,
        touches=args.touches, seed=args.seed, workers=args.workers, progress=not args.quiet,
        **({} if args.noise is None else {"noise": args.noise}),
        **({} if args.sensing == "exact" else {"sensing": args.sensing}),
        **({} if args.skin is None else {"skin": args.skin}),
    )  # fmt: skip
    _print_json(result)
    return 0


def _policies_epilog() -> str:
    from hapticsim.envs.policies import POLICY_NAMES

    return (
        f"policies (--policy): {', '.join(POLICY_NAMES)}, or learned:PATH (a weight file made by "
        "scripts/train_policy.py). Episode i uses seed SEED + i: every policy meets the same "
        "objects, rough positions and noise, so results pair episode by episode."
    )


def add_policies_parser(sub: Any) -> None:
    """``hapticsim policies evaluate`` (exploration policies on HapticExplore-v0, SPEC §6)."""
    from hapticsim.data.distributions import OBJECT_KINDS
    from hapticsim.envs.backends import BACKENDS

    policies = sub.add_parser("policies", help="exploration policies: evaluate one (JSON)")
    cmds = policies.add_subparsers(dest="policies_command", required=True, parser_class=_Parser)
    p = cmds.add_parser(
        "evaluate", help="epsilon after 1..T touches of a policy over many objects (JSON)"
    )
    p.lazy_epilog = _policies_epilog
    p.add_argument("--policy", required=True, help="random, paper, uncertainty, information, "
                   "learned, learned-touch or learned:PATH")  # fmt: skip
    p.add_argument("--backend", choices=BACKENDS, default="analytic")
    p.add_argument("--objects", choices=OBJECT_KINDS, default="random")
    p.add_argument("--episodes", type=_positive_int, default=50, help="episodes (default 50)")
    p.add_argument("--touches", type=_positive_int, default=10, help="touches per episode "
                   "(default 10)")  # fmt: skip
    p.add_argument("--seed", type=_seed, default=0, help="root seed: episode i uses SEED + i")
    p.add_argument(
        "--noise", type=float, default=None,
        help="relative sensor noise sigma_N in [0, 1] (default: the environment's, 0.02)",
    )  # fmt: skip
    p.add_argument(
        "--sensing", choices=("exact", "tactile"), default="exact",
        help="exact contacts, or contacts estimated from taxel pads (the policies also see the "
        "pads' images, as on HapticExploreTactile-v0)",
    )  # fmt: skip
    p.add_argument(
        "--skin", default=None,
        help="with --sensing tactile: ideal (default), vision, capacitive or a skin .toml file",
    )  # fmt: skip
    p.add_argument(
        "--workers", type=_positive_int, default=None, help="processes (default: all cores)"
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_policies_evaluate)
