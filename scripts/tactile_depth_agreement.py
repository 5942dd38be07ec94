"""MuJoCo's <tactile> depth against hapticsim's own taxel model, on primitives (issue 19 item 2).

A free fingertip sphere (radius 8 mm) carrying the default pad (21 x 21 taxels, 1.5 mm) is put
(kinematically, ``mj_forward``) against a MuJoCo primitive object at penetrations 0.1-1 mm and
pad tilts 0-60 deg; MuJoCo's sensor reads the primitive's analytic signed distance, hapticsim's
model (:func:`hapticsim.perception.tactile.taxel_depths`) the same solid's inside test along each
taxel's
normal. Prints JSON: per primitive, the taxels lit by either, the largest |difference| and the
largest difference beyond the stated bound ``delta^2 / (4 R)`` (docs/tactile/README.md).

    python scripts/tactile_depth_agreement.py [--out docs/tactile/depth_agreement.json]
"""

from __future__ import annotations

import argparse
import json
import sys

import mujoco
import numpy as np

from hapticsim._files import write_json
from hapticsim.geometry import Superquadric
from hapticsim.geometry.rays import raycast
from hapticsim.geometry.rotations import rotvec_to_matrix
from hapticsim.perception.tactile import PadLayout, taxel_depths
from hapticsim.sim.tactile import add_mujoco_pads

RADIUS = 0.008


class _Primitive:
    """An exact solid of a MuJoCo primitive (inside test, centre, bounding radius)."""

    def __init__(self, kind: str, size: list[float]) -> None:
        self.kind, self.size = kind, np.asarray(size, float)
        self.center = np.zeros(3)
        self.bounding_radius = float(np.linalg.norm(self.size) + self.size.max())

    def normals(self, p: np.ndarray) -> np.ndarray:
        """(n, 3) outward unit normals at surface points."""
        s, p = self.size, np.asarray(p, float)
        if self.kind == "box":
            axis = np.argmax(np.abs(p) / s, axis=1)
            out = np.zeros_like(p)
            out[np.arange(len(p)), axis] = np.sign(p[np.arange(len(p)), axis])
            return out
        if self.kind == "cylinder":
            cap = np.abs(p[:, 2]) / s[1] >= np.hypot(p[:, 0], p[:, 1]) / s[0]
            radial = np.column_stack([p[:, 0], p[:, 1], np.zeros(len(p))])
            out = np.where(cap[:, None], np.column_stack([0 * p[:, :2], np.sign(p[:, 2])]), radial)
            return out / np.linalg.norm(out, axis=1, keepdims=True)
        out = p - np.column_stack([0 * p[:, :2], np.clip(p[:, 2], -s[1], s[1])])
        return out / np.linalg.norm(out, axis=1, keepdims=True)

    def edge_distance(self, point: np.ndarray) -> float:
        """Distance [m] from a surface point to the nearest edge of its face (inf: none)."""
        s, p = self.size, np.abs(np.asarray(point, float))
        if self.kind == "box":
            axis = int(np.argmax(p / s))
            return float(min(s[k] - p[k] for k in range(3) if k != axis))
        if self.kind == "cylinder":
            r = float(np.hypot(p[0], p[1]))
            return float(s[0] - r) if p[2] / s[1] >= r / s[0] else float(s[1] - p[2])
        return float("inf")

    def contains(self, p: np.ndarray) -> np.ndarray:
        s, (x, y, z) = self.size, np.asarray(p, float).T
        if self.kind == "box":
            return (np.abs(x) <= s[0]) & (np.abs(y) <= s[1]) & (np.abs(z) <= s[2])
        if self.kind == "cylinder":
            return (x * x + y * y <= s[0] ** 2) & (np.abs(z) <= s[1])
        if self.kind == "capsule":
            zc = np.clip(z, -s[1], s[1])
            return x * x + y * y + (z - zc) ** 2 <= s[0] ** 2
        raise ValueError(self.kind)


PRIMITIVES = {
    "sphere": ("sphere", [0.02, 0, 0], Superquadric([0.02] * 3, [1.0, 1.0])),
    "ellipsoid": ("ellipsoid", [0.03, 0.02, 0.015], Superquadric([0.03, 0.02, 0.015], [1, 1])),
    "box": ("box", [0.03, 0.02, 0.015], _Primitive("box", [0.03, 0.02, 0.015])),
    "capsule": ("capsule", [0.015, 0.02, 0], _Primitive("capsule", [0.015, 0.02])),
    "cylinder": ("cylinder", [0.015, 0.02, 0], _Primitive("cylinder", [0.015, 0.02])),
}


def _model(kind: str, size: list[float], layout: PadLayout) -> mujoco.MjModel:
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="object", type=getattr(mujoco.mjtGeom, f"mjGEOM_{kind.upper()}"),
                            size=size)  # fmt: skip
    body = spec.worldbody.add_body(name="tip")
    body.add_freejoint()
    body.add_geom(name="tip", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RADIUS, 0, 0], mass=0.02)
    add_mujoco_pads(spec, [("tip", np.zeros(3), np.array([1.0, 0, 0, 0]), layout)])
    return spec.compile()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="also write the JSON here")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    layout = PadLayout(21, 21, 0.0015, RADIUS, [0, 0, -1], [0, 1, 0], [0, 0, 0])
    pos, nrm, _ = layout.taxels
    out: dict[str, object] = {"radius": RADIUS, "grid": [21, 21, 0.0015], "seed": args.seed}
    for name, (kind, size, solid) in PRIMITIVES.items():
        model = _model(kind, size, layout)
        data = mujoco.MjData(model)
        rows: dict[str, dict[str, float]] = {}
        for _ in range(120):
            # a surface point and its outward normal
            direction = rng.normal(size=3)
            direction /= np.linalg.norm(direction)
            s_hit = raycast(solid, 0.2 * direction, -direction, 0.2)
            surface = (0.2 - s_hit) * direction
            normal = solid.normals(surface[None])[0]
            delta = rng.uniform(0.1e-3, 1.0e-3)
            tilt = rotvec_to_matrix(rng.normal(size=3) * np.radians(30))
            centre = surface + (RADIUS - delta) * normal
            # pad faces the object: its centre normal (0, 0, -1) turned to -normal, tilted
            z = -normal
            x = np.cross([0.0, 0.0, 1.0], z)
            x = x / np.linalg.norm(x) if np.linalg.norm(x) > 1e-6 else np.array([1.0, 0, 0])
            rot = tilt @ np.column_stack([x, np.cross(z, x), z]) @ np.diag([1, -1, -1])
            quat = np.zeros(4)
            mujoco.mju_mat2Quat(quat, rot.ravel())
            data.qpos[:3], data.qpos[3:7] = centre, quat
            mujoco.mj_forward(model, data)
            if data.ncon == 0:
                continue
            penetration = -float(data.contact.dist.min())  # the true one, MuJoCo's contact
            mj = np.asarray(data.sensordata[: layout.count]).reshape(layout.shape)
            own = taxel_depths(solid, pos @ rot.T + centre, nrm @ rot.T, RADIUS)
            lit = (mj > 0) | (own > 0)
            if not lit.any():
                continue
            # near an edge when the contact disc (radius sqrt(2 R delta)) reaches it
            edge = getattr(solid, "edge_distance", lambda _: np.inf)(surface)
            near = edge < np.sqrt(2 * RADIUS * penetration) + 0.5e-3 or penetration > 1.2 * delta
            kind_of = "edge" if near else "face"
            diff = np.abs(own - mj)[lit]
            row = rows.setdefault(
                kind_of,
                {
                    "presses": 0,
                    "lit_taxels": 0,
                    "max_abs_m": 0.0,
                    "max_relative": 0.0,
                    "max_beyond_bound_m": -1.0,
                },
            )
            row["presses"] += 1
            row["lit_taxels"] += int(lit.sum())
            row["max_abs_m"] = max(row["max_abs_m"], float(diff.max()))
            row["max_relative"] = max(row["max_relative"], float(diff.max() / penetration))
            bound = penetration**2 / (4 * RADIUS)
            row["max_beyond_bound_m"] = max(row["max_beyond_bound_m"], float(diff.max() - bound))
        out[name] = rows
        for kind_of, row in rows.items():
            print(
                f"{name} {kind_of}: {row['presses']} presses, {row['lit_taxels']} taxels, max "
                f"|own - mujoco| {row['max_abs_m'] * 1e3:.4f} mm ({row['max_relative']:.3f} "
                f"of the penetration), beyond delta^2/(4R): "
                f"{row['max_beyond_bound_m'] * 1e3:.4f} mm",
                file=sys.stderr,
            )
    text = json.dumps(out, indent=2)
    print(text)
    if args.out:
        write_json(args.out, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
