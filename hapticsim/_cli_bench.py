"""``hapticsim bench ...``: the benchmark protocol's commands (thin, as the rest of the CLI)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from hapticsim._cli_common import _Parser, _positive_int, _print_json


def _cmd_tasks(args: argparse.Namespace) -> int:
    from hapticsim.bench import task_names

    sys.stdout.write("\n".join(task_names()) + "\n")
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    from hapticsim._files import check_output_path
    from hapticsim.bench.runner import run_bench, write_results

    out = check_output_path(args.out, (".json",))
    results = run_bench(args.task, args.policy, args.episodes, estimator=args.estimator,
                        split=args.split, workers=args.workers, scheduler=args.scheduler,
                        progress=not args.quiet, command=["hapticsim", *args.argv])  # fmt: skip
    write_results(results, out)
    s = results["summary"]
    _print_json({"task": args.task, "policy": args.policy, "episodes": args.episodes,
                 "out": str(out), "iou_area": s["iou"]["area_mean"],
                 "f_score_2.5_area": s["f_score_2.5"]["area_mean"],
                 "seconds": results["seconds"]})  # fmt: skip
    return 0


def _cmd_report(args: argparse.Namespace) -> int:
    from hapticsim.bench.report import write_report

    files = write_report(args.results, args.out)
    _print_json({k: str(v) for k, v in files.items()})
    return 0


def _cmd_record(args: argparse.Namespace) -> int:
    from hapticsim.bench.record import record_dataset

    _print_json(record_dataset(args.task, args.policy, args.episodes, args.dataset,
                               split=args.split, root=args.root, progress=not args.quiet))
    return 0


def add_bench_parser(sub: Any) -> None:
    """``hapticsim bench tasks | run | record | report`` (SPEC §13)."""
    bench = sub.add_parser("bench", help="the benchmark protocol: tasks, runs, a leaderboard")
    cmds = bench.add_subparsers(dest="bench_command", required=True, parser_class=_Parser)
    p = cmds.add_parser("tasks", help="list the tasks, one per line")
    p.set_defaults(func=_cmd_tasks)
    p = cmds.add_parser("run", help="a policy on a task's episodes; every metric after every "
                        "touch (JSON results file)")  # fmt: skip
    p.add_argument("task", help="FAMILY/SENSING/BACKEND/tTOUCHES (`hapticsim bench tasks`)")
    p.add_argument("--policy", required=True, help="random, paper, uncertainty, information, "
                   "learned, learned-touch, learned:PATH, or a lab's class MODULE:ATTR")
    p.add_argument("--estimator", default="env-nH", help="env-nH (the environment's own fit, "
                   "default), env-multi (its multi schedule), nML, multi, gpis, supertoroid or "
                   "a lab's fitter MODULE:ATTR (fitted at touches 5, 10, 20 and the last)",
                   )  # fmt: skip
    p.add_argument("--episodes", type=_positive_int, default=30)
    p.add_argument("--split", choices=("dev", "test"), default="test")
    p.add_argument("--out", required=True, help="results file (.json)")
    p.add_argument("--workers", type=_positive_int, default=None, help="processes (default: all "
                   "cores)")  # fmt: skip
    p.add_argument("--scheduler", default=None, help="a Dask cluster (tcp://host:port or local:N)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_run)
    p = cmds.add_parser("record", help="a policy's episodes of a task as a Minari dataset "
                        "(extra minari)")  # fmt: skip
    p.add_argument("task", help="FAMILY/SENSING/BACKEND/tTOUCHES (`hapticsim bench tasks`)")
    p.add_argument("--policy", required=True, help="a policy name or MODULE:ATTR")
    p.add_argument("--episodes", type=_positive_int, default=100)
    p.add_argument("--dataset", required=True, help="Minari's id, NAMESPACE/NAME-vN")
    p.add_argument("--split", choices=("dev", "test"), default="test")
    p.add_argument("--root", default=None, help="the datasets folder (default: Minari's, "
                   "MINARI_DATASETS_PATH)")  # fmt: skip
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.set_defaults(func=_cmd_record)
    p = cmds.add_parser("report", help="a leaderboard of results files (Markdown and HTML)")
    p.add_argument("results", nargs="+", help="results files of `hapticsim bench run`")
    p.add_argument("--out", required=True, help="folder for leaderboard.md and index.html")
    p.set_defaults(func=_cmd_report)
