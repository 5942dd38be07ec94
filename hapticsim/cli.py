"""The ``hapticsim`` command line (SPEC §6): thin — parse, call, print.

Where a command prints JSON, stdout carries only that JSON; progress and logs go to stderr.
Any :class:`~hapticsim.errors.HapticsimError` (and a bad command line) ends with one line on
stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import atexit
import io
import os
import sys
import textwrap
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim._cli_bench import add_bench_parser
from hapticsim._cli_common import (
    EXIT_BAD_INPUT,
    EXIT_INTERRUPTED,
    _Parser,
    _parts,
    _positive_float,
    _print_json,
    _seed,
)
from hapticsim._cli_suites import add_policies_parser, add_suite_parser
from hapticsim._files import check_output_path
from hapticsim.errors import HapticsimError, InvalidInputError
from hapticsim.geometry import solid_from_json


def _explore_epilog() -> str:
    """The object kinds and the registered strategies (imports the simulator: help only)."""

    from hapticsim.sim.strategies import STRATEGIES

    lines = ["object kinds (--object):"]
    kinds = (
        ("body", "tapered_box, cube, cylinder, ellipsoid (the paper's bodies)"),
        ("superquadric", "a .json file: a superquadric (SPEC §6), a union of superquadrics"
                         " (SPEC §10: {\"parts\": [...]}) or a fit result"),
        ("random", "a random superquadric without taper, drawn from --seed"),
        ("random_tapered", "a random tapered superquadric, drawn from --seed"),
        ("random_composite", "a union of 2-4 overlapping random superquadrics, drawn from"
                             " --seed"),
        ("random_holed", "a random ring (a supertoroid: a superquadric with a hole), drawn from"
                         " --seed"),
        ("random_handled", "a random body with a ring handle (a union of a superquadric and a"
                           " supertoroid), drawn from --seed"),
        ("mesh", "a closed .stl, .obj, .ply or .off file in metres (--scale converts);"
                 " centred at its centroid unless --pose; non-convex ones need coacd"),
        ("pybullet:NAME", "a model of the installed pybullet_data (extra objects): duck,"
                          " soccerball, jenga, domino, random/000 ... random/999, or a"
                          " .urdf/mesh path inside pybullet_data"),
    )  # fmt: skip
    rows = list(kinds)
    rows.append(("", ""))
    for name in sorted(STRATEGIES):
        doc = (STRATEGIES[name].__doc__ or "").strip().split("\n\n")[0]
        rows.append((name, " ".join(doc.split())))
    rows += [
        ("uncertainty", "the environment's policy: touch where the current fit is least"
                        " supported by the contacts so far (refits after every touch)"),
        ("information", "the environment's policy touching where a contact is expected to"
                        " reduce the fit's posterior surface variance most"),
        ("learned", "the environment's shipped learned policy (learned:PATH: a weight file)"),
        ("learned-touch", "the shipped policy that learned from the touch history itself"),
        ("random", "the environment's random touches"),
    ]
    for k, v in rows:
        if not k and not v:
            lines.append("strategies (--strategy):")
            continue
        wrapped = textwrap.wrap(v, 58) or [""]
        lines.append(f"  {k:<18}{wrapped[0]}")
        lines += [" " * 20 + w for w in wrapped[1:]]
    return "\n".join(lines)


# ----------------------------------------------------------------------------- commands
def _cmd_synth(args: argparse.Namespace) -> int:
    from hapticsim.data import io
    from hapticsim.data.objects import ObjectSpec
    from hapticsim.data.synthetic import synthetic_dataset

    # Check both outputs first so that bad input never leaves one of them written.
    io.check_output_path(args.out, io.CONTACT_SUFFIXES)
    if args.truth_out:
        io.check_output_path(args.truth_out)
    spec = ObjectSpec(args.body)
    if spec.kind in ("mesh", "pybullet"):
        raise InvalidInputError(
            f"synth draws the paper's patterns on superquadrics and unions, got a mesh "
            f"({args.body}): explore it with the hand (hapticsim explore --object ...)"
        )
    # a random kind's shape has its own stream: the contacts keep the seed's as before
    truth = spec.resolve(np.random.default_rng(np.random.SeedSequence(args.seed).spawn(1)[0]))
    contacts = synthetic_dataset(truth, noise=args.noise, rng=args.seed, count=args.count)
    io.write_contacts(args.out, contacts)
    if args.truth_out:
        io.write_json(args.truth_out, truth.to_dict())
    _print_json({"contacts": str(args.out), "count": len(contacts), "truth": truth.to_dict()})
    return 0


def _cmd_score(args: argparse.Namespace) -> int:
    from hapticsim.data.objects import MESH_SUFFIXES, load_mesh
    from hapticsim.metrics import score

    estimate = solid_from_json(args.estimate)
    if Path(args.truth).suffix.lower() in MESH_SUFFIXES:  # a mesh truth, as it stands
        truth = load_mesh(args.truth)
    else:
        truth = solid_from_json(args.truth)
    _print_json(score(estimate, truth, rng=args.seed).to_dict())
    return 0


def _cmd_fit(args: argparse.Namespace) -> int:
    from hapticsim.data.io import check_output_path, write_json
    from hapticsim.fitting import fit
    from hapticsim.fitting.kernels import start_background
    from hapticsim.fitting.methods import SOLID_METHODS

    if args.out:
        check_output_path(args.out)  # before the fit, not after it
    if args.uncertainty and args.method in SOLID_METHODS:
        raise InvalidInputError(
            f"--uncertainty is for one superquadric, not for --method {args.method}"
        )
    if args.contact_sigma and args.method != "nML":
        raise InvalidInputError("--contact-sigma is for --method nML only")
    if (args.noise is not None or args.free_space) and args.method not in ("nML", "multi"):
        raise InvalidInputError("--noise and --free-space are for --method nML and multi only")
    if args.parts is not None and args.method != "multi":
        raise InvalidInputError("--parts is for --method multi only")
    if args.holes and args.method != "multi":
        raise InvalidInputError("--holes is for --method multi only")
    # Every file is read and checked before the first fit: a bad one costs no fitting time.
    inputs = [_fit_inputs(path, args) for path in args.contacts]
    compiling = start_background(args.method)  # a fresh installation: in parallel, with progress
    if compiling is not None:
        compiling.wait()  # then the first fit loads the kernels (its setup_seconds)
    results = []
    for path, (contacts, extra) in zip(args.contacts, inputs, strict=True):
        result = fit(contacts.points, contacts.normals, method=args.method, budget=args.budget,
                     rng=args.seed, uncertainty=args.uncertainty, **extra)  # fmt: skip
        results.append(result.to_dict() if len(inputs) == 1 else
                       {"contacts": str(path), **result.to_dict()})  # fmt: skip
    out = results[0] if len(results) == 1 else results
    if args.out:
        write_json(args.out, out)
    _print_json(out)
    return 0


def _fit_inputs(path: str, args: argparse.Namespace) -> tuple[Any, dict]:
    """One contacts file of ``hapticsim fit`` and the keyword arguments of its fit."""
    from hapticsim.data.io import FREE_SPACE_KEY, read_contacts

    contacts = read_contacts(path)
    extra: dict = {}
    if args.noise is not None:
        extra["noise"] = args.noise
    if args.method == "multi":
        extra["parts"] = args.parts
        extra["holes"] = args.holes
    if args.contact_sigma:
        if "sigma" not in contacts.extra:
            raise InvalidInputError(
                f"{path} has no `sigma` array for --contact-sigma (explore "
                "--sensing tactile writes one; found: "
                f"{sorted(contacts.extra) or 'nothing'})"
            )
        extra["sigma"] = contacts.extra["sigma"]
        if "sigma_normal" in contacts.extra:
            extra["sigma_normal"] = contacts.extra["sigma_normal"]
    if args.free_space:
        if FREE_SPACE_KEY not in contacts.extra:
            raise InvalidInputError(
                f"{path} has no `{FREE_SPACE_KEY}` array for --free-space (found: "
                f"{sorted(contacts.extra) or 'nothing'})"
            )
        extra["free"] = contacts.extra[FREE_SPACE_KEY].reshape(-1, 3)
    return contacts, extra


def _cmd_explore(args: argparse.Namespace) -> int:
    from hapticsim.fitting.kernels import start_background
    from hapticsim.fitting.methods import FIT_METHODS

    compiling = None
    if args.method in FIT_METHODS:  # a fresh installation: compile while the simulator loads
        compiling = start_background(args.method, stream=io.StringIO() if args.quiet else None)
    try:
        summary = _explore_from_args(args)
    except BaseException:
        if compiling is not None:
            compiling.stop()
        raise
    return _explore_done(summary)


def _explore_from_args(args: argparse.Namespace) -> dict:
    from hapticsim.exploration import explore

    return explore(
        object_name=args.object,
        strategy=args.strategy,
        noise=args.noise,
        method=args.method,
        seed=args.seed,
        out_dir=args.out,
        render=args.render,
        progress=not args.quiet,
        count=args.count,
        scale=args.scale,
        pose=args.pose,
        hand=args.hand,
        video=args.video,
        sensing=args.sensing,
        skin=args.skin,
        taxel_model=args.taxel_model,
        steer_on=args.steer_on,
        holes=args.holes,
        object_dynamics=_dynamics_from_args(args),
        force_limit=args.force_limit,
    )


def _dynamics_from_args(args: argparse.Namespace) -> Any:
    """``--object-dynamics`` and its options as an ObjectDynamics (SPEC §12)."""
    from hapticsim.sim.dynamics import ObjectDynamics

    given = {"--object-mass": args.object_mass, "--object-density": args.object_density,
             "--clamp-stiffness": args.clamp_stiffness}  # fmt: skip
    if args.object_dynamics == "fixed":
        named = [k for k, v in given.items() if v is not None]
        if named:
            raise InvalidInputError(
                f"{', '.join(named)} is for a free object (--object-dynamics resting or held)"
            )
        return "fixed"
    if args.clamp_stiffness is not None and args.object_dynamics != "held":
        raise InvalidInputError("--clamp-stiffness is for --object-dynamics held")
    extra = {"mass": args.object_mass}
    if args.object_density is not None:
        extra["density"] = args.object_density
    if args.clamp_stiffness is not None:
        extra["clamp_stiffness"] = args.clamp_stiffness
    return ObjectDynamics(kind=args.object_dynamics, **extra)


def _explore_done(summary: dict) -> int:
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
        scheduler=args.scheduler,
    )
    _print_json(summary)
    return 0


# ----------------------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``hapticsim`` (exposed for tests and docs)."""
    from hapticsim.data.bodies import BODY_NAMES
    from hapticsim.fitting.methods import DEFAULT_BUDGET, FIT_METHODS

    parser = _Parser(
        prog="hapticsim",
        description="Haptic exploration testbed: superquadric recovery from contacts.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("synth", help="synthetic contact data of a body (paper Section III-A)")
    p.add_argument(
        "body",
        help=f"one of {', '.join(BODY_NAMES)}, a superquadric or union JSON file, random, "
        "random_tapered, random_composite or random_holed (drawn from --seed)",
    )  # fmt: skip
    p.add_argument("--noise", type=float, default=0.1, help="relative noise sigma_N (default 0.1)")
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument("--count", type=int, default=150, help="number of contacts (default 150)")
    p.add_argument("--out", default="contacts.npz", help=".npz or .csv (default contacts.npz)")
    p.add_argument("--truth-out", default=None, help="also write the true solid's JSON")
    p.set_defaults(func=_cmd_synth)

    p = sub.add_parser("score", help="quality measures of an estimate against the truth")
    p.add_argument("estimate", help="superquadric, union (SPEC §10) or fit-result JSON")
    p.add_argument(
        "truth",
        help="superquadric or union JSON, or a mesh file (.stl/.obj/.ply/.off, metres, as it is)",
    )  # fmt: skip
    p.add_argument("--seed", type=_seed, default=0, help="seed of the volume sampling")
    p.set_defaults(func=_cmd_score)

    p = sub.add_parser("fit", help="fit a superquadric to contacts files")
    p.add_argument(
        "contacts", nargs="+",
        help=".npz or .csv contacts file(s) (SPEC §6); with several, the JSON is a list of "
        "results, each with its `contacts` file",
    )  # fmt: skip
    p.add_argument(
        "--method", choices=FIT_METHODS, default="nH",
        help="the paper's LS, H, nLS, nH (SPEC §3), nML: maximum likelihood for noisy data, "
        "multi: a union of superquadrics (SPEC §10), gpis: a GP implicit surface, or "
        "supertoroid: a superquadric with a hole",
    )  # fmt: skip
    p.add_argument(
        "--parts", type=_parts, default=None, metavar="K|auto",
        help="multi: the number of parts, or auto (default: chosen by its criterion, up to 4)",
    )  # fmt: skip
    p.add_argument(
        "--holes", action="store_true",
        help="multi: also fit a supertoroid and keep it where it explains the contacts better",
    )  # fmt: skip
    p.add_argument(
        "--noise", type=float, default=None,
        help="nML, multi: the known relative sensor noise sigma_N (default: estimated)",
    )  # fmt: skip
    p.add_argument(
        "--free-space", action="store_true",
        help="nML, multi: keep the solid out of the file's `free_space` points (where the "
        "fingertip was)",
    )  # fmt: skip
    p.add_argument(
        "--contact-sigma", action="store_true",
        help="nML: weigh each contact by the file's `sigma` (its standard deviation [m]) and "
        "`sigma_normal` [rad], as explore --sensing tactile writes them",
    )  # fmt: skip
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument(
        "--budget", type=int, default=None,
        help=f"EOF evaluations (default {DEFAULT_BUDGET}; nML: nH's search plus its ML stages)",
    )  # fmt: skip
    p.add_argument("--out", default=None, help="also write the result JSON here")
    p.add_argument(
        "--uncertainty", action="store_true",
        help="add the estimate's uncertainty (Laplace at the optimum): standard deviations, "
        "50 and 90 %% intervals of the volume, 90 %% of the semi-axes (not for multi)",
    )  # fmt: skip
    p.set_defaults(func=_cmd_fit)

    p = sub.add_parser(
        "explore",
        help="simulated haptic exploration, fit and score",
        description="Explore an object with the simulated hand (planning on a vision estimate\n"
        "from one noisy depth image), fit a superquadric and score it against the truth.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.lazy_epilog = _explore_epilog
    p.add_argument(
        "--object", default="cube",
        help="a body name, a superquadric or union .json, random, random_tapered, "
        "random_composite, random_holed, a mesh file (.stl/.obj/.ply/.off) or pybullet:NAME; "
        "default cube "
        "(kinds below)",
    )  # fmt: skip
    p.add_argument(
        "--scale", type=_positive_float, default=1.0,
        help="factor from the object file's units to metres (default 1; 0.001 for mm)",
    )  # fmt: skip
    p.add_argument(
        "--pose", default=None, metavar="X,Y,Z[,QW,QX,QY,QZ]",
        help="place the object's own frame at this position [m] and orientation (quaternion, "
        "w first); default: a mesh's centroid at the origin, a superquadric as it is",
    )  # fmt: skip
    p.add_argument(
        "--strategy", default="paper", help="exploration strategy (default paper; list below)"
    )
    p.add_argument("--noise", type=float, default=0.0, help="sensor noise sigma_N (default 0)")
    p.add_argument("--method", choices=FIT_METHODS, default="nH")
    p.add_argument("--holes", action="store_true", help="--method multi: also fit a "
                   "supertoroid and keep it where it explains the contacts better")  # fmt: skip
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument(
        "--out", default=None, help="output directory (default runs/OBJECT-STRATEGY-seedN)"
    )
    p.add_argument("--count", type=int, default=150, help="contacts to gather (default 150)")
    p.add_argument("--render", action="store_true", help="also render the scene (MUJOCO_GL=egl)")
    p.add_argument(
        "--hand", default="hapticsim",
        help="hapticsim (default), shadow, adroit (pip install 'hapticsim[hands]') or a TOML "
        "hand description (docs/hands.md)",
    )  # fmt: skip
    p.add_argument(
        "--video", nargs="?", const="mp4", choices=("mp4", "gif"), default=None,
        help="also write exploration.mp4 (default; pip install 'hapticsim[video]') or .gif",
    )  # fmt: skip
    p.add_argument(
        "--sensing", choices=("exact", "tactile"), default="exact",
        help="exact: MuJoCo's contacts (default); tactile: contacts estimated from a taxel pad "
        "on every fingertip (writes tactile.npz)",
    )  # fmt: skip
    p.add_argument(
        "--skin", default=None, metavar="PRESET|FILE.toml",
        help="with --sensing tactile: ideal (default), vision, capacitive, elastomer or "
        "gelsight_mini (these two need the fem extra) or a skin file",
    )  # fmt: skip
    p.add_argument(
        "--taxel-model", default="hapticsim", choices=("hapticsim", "mujoco"),
        help="with --sensing tactile: hapticsim's own taxel model against the exact solid "
        "(default) or MuJoCo's <tactile> sensor",
    )  # fmt: skip
    p.add_argument(
        "--steer-on", default="skin", choices=("skin", "contacts"),
        help="with --sensing tactile: what probing and contour following steer on: the "
        "skin's estimated contacts, a frame every 3 control ticks (default), or MuJoCo's contacts",
    )  # fmt: skip
    p.add_argument(
        "--object-dynamics", choices=("fixed", "resting", "held"), default="fixed",
        help="fixed: a static object (default); resting: a free object in a cradle under "
        "gravity; held: a free object in a stiff clamp (SPEC §12)",
    )  # fmt: skip
    p.add_argument("--object-mass", type=float, default=None, metavar="KG",
                   help="a free object's mass [kg] (default: from its density)")  # fmt: skip
    p.add_argument("--object-density", type=float, default=None, metavar="KG/M3",
                   help="a free object's density [kg/m^3] (default 500)")  # fmt: skip
    p.add_argument("--clamp-stiffness", type=float, default=None, metavar="N/M",
                   help="--object-dynamics held: the clamp's stiffness [N/m] (default 2000)")
    p.add_argument("--force-limit", type=float, default=None, metavar="N",
                   help="the largest normal force a fingertip presses with [N] (gentle "
                   "exploration; default: no limit)")  # fmt: skip
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_explore)

    p = sub.add_parser("reproduce", help="regenerate the paper's Fig. 4 / Fig. 5")
    p.add_argument("which", choices=("fig4", "fig5", "all"))
    p.add_argument("--out", default="runs/reproduce", help="output directory")
    p.add_argument("--runs", type=int, default=10, help="runs (data sets) per setting (default 10)")
    p.add_argument("--seed", type=_seed, default=0)
    workers = p.add_mutually_exclusive_group()
    workers.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    workers.add_argument(
        "--scheduler", default=None, help="run on a Dask cluster: tcp://host:port or local:N"
    )
    p.add_argument(
        "--results", default=None, help="also write the Markdown report here (e.g. RESULTS.md)"
    )
    p.add_argument(
        "--figures-dir", default=None, help="pictures of the report (default: docs/figures)"
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_reproduce)

    p = sub.add_parser(
        "view",
        help="a 3-D viewer of an explore run in the browser (pip install 'hapticsim[viewer]')",
        description="Serve a viewer of one explore run (truth, contacts and normals by finger, "
        "the estimate after every touch with its epsilon, the hand, taxel images) with a slider "
        "over the touches, or export it as one HTML page that opens offline.",
    )
    p.add_argument("run_dir", metavar="RUN_DIR", help="an explore run's directory (--out)")
    p.add_argument("--port", type=int, default=8080, help="port to serve on (default 8080)")
    p.add_argument(
        "--host", default="127.0.0.1",
        help="address to bind (default 127.0.0.1, this machine only; 0.0.0.0 for all)",
    )  # fmt: skip
    p.add_argument(
        "--export", default=None, metavar="FILE.html",
        help="write one self-contained page replaying the run instead of serving it",
    )  # fmt: skip
    p.add_argument(
        "--estimate-every", type=int, default=1, metavar="N",
        help="refit the estimate every N touches (default 1: after every touch)",
    )  # fmt: skip
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=_cmd_view)

    add_suite_parser(sub)
    add_policies_parser(sub)
    add_bench_parser(sub)
    return parser


def _cmd_view(args: argparse.Namespace) -> int:
    from hapticsim.viewer.run import load_run, replay_states
    from hapticsim.viewer.serve import export_html, require_viser, serve

    if not 0 < args.port < 65536:
        raise InvalidInputError(f"--port must be in 1..65535, got {args.port}")
    run = load_run(args.run_dir)  # names the run's missing files, with or without viser
    if args.export:
        check_output_path(args.export, (".html", ".htm"))
    require_viser()  # the extra is installed, before the fits
    states = replay_states(run, args.estimate_every, progress=None if args.quiet else _fits_bar())
    if args.export:
        path = export_html(run, states, args.export)
        _print_json({"run": str(run.path), "export": str(path), "states": len(states)})
        return 0
    serve(run, states, host=args.host, port=args.port)
    return 0


def _fits_bar() -> Any:
    """A progress callback drawing the replay's fits as a bar on stderr."""
    from tqdm import tqdm

    bar: list[Any] = []

    def report(done: int, total: int) -> None:
        if not bar:
            bar.append(tqdm(total=total, desc="estimates after each touch", unit="fit",
                            file=sys.stderr, leave=False))  # fmt: skip
        bar[0].update(done - bar[0].n)
        if done >= total:
            bar[0].close()

    return report


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``hapticsim`` console script; returns the exit status.

    Bad input (any :class:`~hapticsim.errors.HapticsimError`) ends with one line on stderr and
    status 2; Ctrl-C, wherever it falls (parsing included), with one line and status 130.
    """
    args = None
    try:
        args = build_parser().parse_args(argv)
        args.argv = list(sys.argv[1:] if argv is None else argv)  # recorded by `suite run`
        return int(args.func(args))
    except HapticsimError as exc:
        message = " ".join(str(exc).split())
        sub = getattr(args, "suite_command", None) or getattr(args, "policies_command", None)
        words = (getattr(args, "command", None), sub)
        command = " ".join(filter(None, ("hapticsim", *words)))
        sys.stderr.write(f"{command}: error: {message}\n")
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        command = "" if args is None else f" {args.command}"
        sys.stderr.write(f"hapticsim{command}: interrupted\n")
        return EXIT_INTERRUPTED


def run() -> None:
    """The ``hapticsim`` console script: :func:`main`, then the process ends.

    When nothing runs any more but this thread, it ends without the interpreter's teardown of
    the modules numba, MuJoCo and matplotlib loaded (0.3-0.5 s of a short command such as
    ``hapticsim fit``): the exit handlers run and the streams are flushed first, as they would
    be. With other threads alive (a viewer, a thread pool) it exits as usual, joining them.
    """
    code = main()
    if threading.active_count() > 1:
        sys.exit(code)
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing more to say
            pass
    os._exit(code)


if __name__ == "__main__":  # pragma: no cover
    run()
