"""Meshes as labs have them: the one repair every mesh goes through before it becomes a solid.

A lab's STL, OBJ or PLY file is rarely the clean, closed, exactly oriented surface a solid needs:
float32 coordinates, vertices repeated per face, zero-area slivers along edges, a small hole,
faces wound the wrong way, a duplicated shell. :func:`repair_mesh` mends what is repairable,
with tolerances scaled to the mesh, and says what it changed (a :class:`MeshRepair`); it refuses
only what is not one solid, saying why. The steps, in order:

1. **merge vertices** closer than :data:`MERGE_TOLERANCE` of the bounding-box diagonal (1e-6:
   16 times the precision of float32 coordinates, so an STL's seams close);
2. **drop faces** that repeat a vertex (collapsed by the merge) and faces that repeat another
   face (a duplicated shell merges onto its original and goes with them);
3. **fix the winding** where neighbouring faces disagree (trimesh);
4. **fill holes** whose boundary loop spans at most :data:`MAX_HOLE` of the diagonal (10 %) by a
   fan around the loop's centroid; a larger hole is refused, naming its size;
5. **collapse slivers**: a zero-area face whose third vertex lies on its longest edge is removed
   by splitting the neighbour across that edge at the vertex (the surface stays closed: dropping
   the sliver alone would open it);
6. **orient** each closed body outward, and **fuse** bodies that overlap or come within
   :data:`TOUCH_GAP`) with manifold3d's boolean union; bodies further apart are refused, naming
   how many and how far apart.

The volume before (where the mesh as read is closed) and after are recorded.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError

#: Vertices nearer than this fraction of the bounding-box diagonal are one vertex.
MERGE_TOLERANCE: float = 1e-6
#: Largest hole filled, as the longest extent of its boundary loop over the diagonal.
MAX_HOLE: float = 0.10
#: Closed bodies nearer than this [m] (nearest vertices) are one object (fused).
TOUCH_GAP: float = 1e-3
#: A face is a sliver when twice its area is below this fraction of the squared diagonal (the
#: threshold below which :class:`~hapticsim.geometry.mesh_solid.MeshSolid` refuses a face).
SLIVER_AREA: float = 1e-14


@dataclass
class MeshRepair:
    """What :func:`repair_mesh` changed (all zero / False: nothing).

    Attributes:
        merged_vertices: vertices merged into others.
        dropped_faces: faces dropped as collapsed or repeated.
        fixed_winding: faces were re-wound to agree with their neighbours.
        filled_holes: holes closed; ``hole_faces`` the faces added.
        collapsed_slivers: zero-area faces removed by splitting their neighbour.
        inverted_bodies: closed bodies turned outward.
        fused_bodies: bodies fused into one by a boolean union (0: one body as read).
        volume_before: volume of the mesh as read, its vertices welded [m^3] (None where it
            is not closed).
        volume_after: volume of the solid [m^3].
    """

    merged_vertices: int = 0
    dropped_faces: int = 0
    fixed_winding: bool = False
    filled_holes: int = 0
    hole_faces: int = 0
    collapsed_slivers: int = 0
    inverted_bodies: int = 0
    fused_bodies: int = 0
    volume_before: float | None = None
    volume_after: float = 0.0
    notes: list[str] = field(default_factory=list)

    @property
    def changed(self) -> bool:
        """True when the repair changed anything."""
        return bool(self.merged_vertices or self.dropped_faces or self.fixed_winding
                    or self.filled_holes or self.collapsed_slivers or self.inverted_bodies
                    or self.fused_bodies)  # fmt: skip

    @property
    def volume_change(self) -> float | None:
        """Relative change of the volume, (after - before) / before (None without before)."""
        if self.volume_before is None or self.volume_before <= 0:
            return None
        return (self.volume_after - self.volume_before) / self.volume_before

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, with ``volume_change``."""
        out = asdict(self)
        out.pop("notes")
        out["volume_change"] = self.volume_change
        return out

    def summary(self) -> str:
        """One line of what changed (``"nothing"`` when nothing did)."""
        parts = [
            f"merged {self.merged_vertices} vertices" if self.merged_vertices else "",
            f"dropped {self.dropped_faces} collapsed or repeated faces" if self.dropped_faces
            else "",
            "fixed the faces' winding" if self.fixed_winding else "",
            f"filled {self.filled_holes} holes ({self.hole_faces} faces)" if self.filled_holes
            else "",
            f"collapsed {self.collapsed_slivers} slivers" if self.collapsed_slivers else "",
            f"turned {self.inverted_bodies} bodies outward" if self.inverted_bodies else "",
            f"fused {self.fused_bodies} bodies" if self.fused_bodies else "",
        ]  # fmt: skip
        text = ", ".join(p for p in parts if p) or "nothing"
        change = self.volume_change
        return text if change is None else f"{text} (volume change {100 * change:+.3f} %)"


def repair_mesh(
    vertices: Any, faces: Any, name: str, unit: float = 1.0
) -> tuple[NDArray[np.float64], NDArray[np.int64], MeshRepair]:
    """One closed, outward solid from a triangle mesh (module docstring).

    Args:
        vertices: (v, 3) float, in the file's units.
        faces: (f, 3) int.
        name: the mesh in messages (its file name).
        unit: metres per file unit (the distances in messages and :data:`TOUCH_GAP` are
            metres).

    Returns:
        vertices (v', 3) [file units] and faces (f', 3) of the solid, and the repair record.

    Raises:
        InvalidInputError: no triangles; vertices that are not finite; a hole larger than
            :data:`MAX_HOLE` (its size named);
            several bodies further apart than :data:`TOUCH_GAP` (how many, how far); a surface
            that stays open.
    """
    import trimesh

    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    if len(f) == 0 or len(v) < 3:
        raise InvalidInputError(f"mesh {name} is empty: it holds no triangles")
    if not np.all(np.isfinite(v)):
        bad = int(np.count_nonzero(~np.all(np.isfinite(v), axis=1)))
        raise InvalidInputError(
            f"mesh {name} has {bad} of {len(v)} vertices with non-finite coordinates (NaN or "
            "infinity): the file is damaged"
        )
    report = MeshRepair()
    diagonal = float(np.linalg.norm(np.ptp(v, axis=0)))
    if diagonal <= 0:
        raise InvalidInputError(f"mesh {name} has no extent: all its vertices coincide")
    welded = trimesh.Trimesh(*_merge_vertices(v, f, MERGE_TOLERANCE * diagonal)[:2], process=False)
    report.volume_before = float(abs(welded.volume)) * unit**3 if welded.is_watertight else None

    # 1-2: merge vertices, drop collapsed and repeated faces
    v, f, report.merged_vertices, report.dropped_faces = _clean(v, f, MERGE_TOLERANCE * diagonal)
    # 3: winding
    mesh = trimesh.Trimesh(v, f, process=False)
    if not mesh.is_winding_consistent:
        trimesh.repair.fix_winding(mesh)
        report.fixed_winding = True
        f = np.asarray(mesh.faces, np.int64)
    # 4: holes
    f, holes, added_v, hole_faces = _fill_holes(v, f, MAX_HOLE * diagonal, name, unit)
    if holes:
        v = np.vstack([v, added_v])
        report.filled_holes, report.hole_faces = holes, hole_faces
    # 5: slivers
    f, report.collapsed_slivers = _collapse_slivers(v, f, SLIVER_AREA * diagonal**2)
    # 6: bodies: orient, fuse what touches, refuse what does not
    v, f, inverted, fused = _one_body(v, f, name, unit)
    report.inverted_bodies, report.fused_bodies = inverted, fused
    report.volume_after = float(trimesh.Trimesh(v, f, process=False).volume) * unit**3
    return v, f, report


def _clean(
    v: NDArray[np.float64], f: NDArray[np.int64], tolerance: float
) -> tuple[NDArray[np.float64], NDArray[np.int64], int, int]:
    """Steps 1-2: vertices within `tolerance` merged, faces that repeat a vertex or another
    face dropped, unused vertices removed; returns (v, f, merged, dropped)."""
    v, f, merged = _merge_vertices(v, f, tolerance)
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
    unique = np.zeros(len(f), bool)
    unique[first] = True
    keep &= unique
    f = f[keep]
    used = np.unique(f)
    remap = np.full(len(v), -1, np.int64)
    remap[used] = np.arange(len(used))
    return v[used], remap[f], merged, int(np.count_nonzero(~keep))


def _merge_vertices(
    v: NDArray[np.float64], f: NDArray[np.int64], tolerance: float
) -> tuple[NDArray[np.float64], NDArray[np.int64], int]:
    """Vertices within `tolerance` of each other as one (the first of each cluster); the count
    leaves out exact copies (an STL file repeats every vertex per face: that is its format, not
    a flaw)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(v).query_pairs(tolerance, output_type="ndarray")
    if len(pairs) == 0:
        return v, f, 0
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(v),) * 2)
    count, label = connected_components(graph, directed=False)
    first = np.full(count, len(v), np.int64)
    np.minimum.at(first, label, np.arange(len(v)))
    order = np.argsort(first)  # clusters in the order of their first vertex
    new_index = np.empty(count, np.int64)
    new_index[order] = np.arange(count)
    distinct = len(np.unique(v, axis=0))
    return v[first[order]], new_index[label][f], distinct - count


def _boundary_loops(f: NDArray[np.int64]) -> list[list[int]] | None:
    """The loops of boundary edges (used by one face), each in its faces' direction; None when
    the boundary is not a set of simple loops (a vertex on two holes, a non-manifold edge)."""
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    key = np.sort(directed, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    uses = counts[inverse.ravel()]
    if np.any(uses > 2):
        return None
    boundary = directed[uses == 1]
    if len(boundary) == 0:
        return []
    nxt: dict[int, int] = {}
    for a, b in boundary:
        if int(a) in nxt:
            return None
        nxt[int(a)] = int(b)
    loops, seen = [], set()
    for start in nxt:
        if start in seen:
            continue
        loop, at = [], start
        while at not in seen:
            seen.add(at)
            loop.append(at)
            if at not in nxt:
                return None
            at = nxt[at]
        if at != start:
            return None
        loops.append(loop)
    return loops


def _fill_holes(
    v: NDArray[np.float64], f: NDArray[np.int64], max_extent: float, name: str, unit: float
) -> tuple[NDArray[np.int64], int, NDArray[np.float64], int]:
    """Close every hole spanning at most `max_extent` by a fan around its loop's centroid;
    returns (faces, holes filled, new vertices, new faces)."""
    loops = _boundary_loops(f)
    if loops is None:
        raise InvalidInputError(
            f"mesh {name} is not a closed surface: edges shared by more than two faces or "
            "holes that touch, which no repair can close"
        )
    if not loops:
        return f, 0, np.zeros((0, 3)), 0
    extents = [float(np.ptp(v[loop], axis=0).max()) for loop in loops]
    if max(extents) > max_extent:
        raise InvalidInputError(
            f"mesh {name} is not a closed surface: {len(loops)} holes, the largest "
            f"{1e3 * unit * max(extents):.3g} mm across (holes up to "
            f"{1e3 * unit * max_extent:.3g} mm, {100 * MAX_HOLE:g} % of its size, are filled)"
        )
    new_vertices, new_faces = [], []
    for loop in loops:
        centre = len(v) + len(new_vertices)
        new_vertices.append(v[loop].mean(axis=0))
        for i, a in enumerate(loop):  # the boundary edge a->b is reversed in the new face
            b = loop[(i + 1) % len(loop)]
            new_faces.append((b, a, centre))
    added = np.asarray(new_faces, np.int64)
    return np.vstack([f, added]), len(loops), np.asarray(new_vertices), len(added)


def _collapse_slivers(
    v: NDArray[np.float64], f: NDArray[np.int64], min_doubled_area: float
) -> tuple[NDArray[np.int64], int]:
    """Remove zero-area faces by splitting the neighbour across each one's longest edge at its
    third vertex (module docstring); faces that cannot be mended so are left (the solid then
    refuses them)."""
    faces = [tuple(int(i) for i in row) for row in f]
    collapsed = 0
    for _ in range(len(faces)):
        tri = v[np.asarray(faces)]
        doubled = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        bad = np.flatnonzero(doubled <= min_doubled_area)
        mended = False
        for k in bad:
            a, b, c = faces[k]
            # the longest edge p -> q and the vertex r on it
            options = [(a, b, c), (b, c, a), (c, a, b)]
            p, q, r = max(options, key=lambda e: float(np.linalg.norm(v[e[0]] - v[e[1]])))
            j = next((i for i, g in enumerate(faces)
                      if i != k and p in g and q in g and len(set(g)) == 3 and r not in g),
                     None)  # fmt: skip
            if j is None:
                continue
            g = faces[j]
            d = next(x for x in g if x not in (p, q))
            # split g's edge at r, keeping g's orientation
            s = g.index(d)
            u, w = g[(s + 1) % 3], g[(s + 2) % 3]  # g = (d, u, w) cyclically, edge u -> w
            new = [(d, u, r), (d, r, w)]
            for i in sorted((k, j), reverse=True):
                faces.pop(i)
            faces.extend(new)
            collapsed += 1
            mended = True
            break
        if not mended:
            break
    return np.asarray(faces, np.int64), collapsed


def _one_body(
    v: NDArray[np.float64], f: NDArray[np.int64], name: str, unit: float
) -> tuple[NDArray[np.float64], NDArray[np.int64], int, int]:
    """Orient each closed body outward; fuse bodies that touch; refuse bodies apart."""
    import trimesh

    mesh = trimesh.Trimesh(v, f, process=False)
    bodies = mesh.split(only_watertight=False)
    if not bodies:
        raise InvalidInputError(f"mesh {name} holds no closed body")
    open_bodies = [b for b in bodies if not b.is_watertight]
    if open_bodies:
        raise InvalidInputError(
            f"mesh {name} is not a closed surface after its repair ({len(open_bodies)} of its "
            f"{len(bodies)} bodies stay open)"
        )
    inverted = 0
    for body in bodies:
        if body.volume < 0:
            body.invert()
            inverted += 1
    if len(bodies) == 1:
        body = bodies[0]
        return np.asarray(body.vertices), np.asarray(body.faces, np.int64), inverted, 0
    groups, gap = _groups(bodies, TOUCH_GAP / unit)
    if groups > 1:
        raise InvalidInputError(
            f"mesh {name} holds {len(bodies)} bodies in {groups} pieces, the nearest "
            f"{1e3 * unit * gap:.3g} mm apart (more than {1e3 * TOUCH_GAP:g} mm): give one "
            "object per file"
        )
    total = None
    for body in bodies:
        part = _manifold(body)
        total = part if total is None else total + part
    assert total is not None
    fused = total.to_mesh()
    out = trimesh.Trimesh(np.asarray(fused.vert_properties[:, :3], np.float64),
                          np.asarray(fused.tri_verts, np.int64), process=False)  # fmt: skip
    if not out.is_watertight:
        raise InvalidInputError(f"mesh {name} is not a closed surface after fusing its bodies")
    # the union's float32 output may hold coincident vertices and slivers of its own
    fv, ff = np.asarray(out.vertices), np.asarray(out.faces, np.int64)
    diagonal = float(np.linalg.norm(np.ptp(fv, axis=0)))
    fv, ff, _, _ = _clean(fv, ff, MERGE_TOLERANCE * diagonal)
    ff, _ = _collapse_slivers(fv, ff, SLIVER_AREA * diagonal**2)
    return fv, ff, inverted, len(bodies)


def _manifold(body: Any) -> Any:
    import manifold3d

    return manifold3d.Manifold(manifold3d.Mesh(
        vert_properties=np.asarray(body.vertices, np.float32),
        tri_verts=np.asarray(body.faces, np.uint32),
    ))  # fmt: skip


def _groups(bodies: list, gap: float) -> tuple[int, float]:
    """How many groups the bodies form when bodies that overlap, or come within `gap` of each
    other (nearest vertices), belong together; and the smallest distance between two groups."""
    from scipy.spatial import cKDTree

    n = len(bodies)
    group = list(range(n))

    def root(i: int) -> int:
        while group[i] != i:
            i = group[i]
        return i

    trees = [cKDTree(np.asarray(b.vertices)) for b in bodies]
    solids = [_manifold(b) for b in bodies]
    boxes = [np.asarray(b.bounds) for b in bodies]
    dist = np.full((n, n), np.inf)
    for i in range(n):
        for j in range(i + 1, n):
            dist[i, j] = dist[j, i] = trees[i].query(np.asarray(bodies[j].vertices))[0].min()
            boxes_meet = np.all(boxes[i][0] <= boxes[j][1]) and np.all(boxes[j][0] <= boxes[i][1])
            overlap = boxes_meet and (solids[i] ^ solids[j]).volume() > 0.0
            if dist[i, j] <= gap or overlap:
                group[root(j)] = root(i)
    roots = [root(i) for i in range(n)]
    apart = [dist[i, j] for i in range(n) for j in range(n) if roots[i] != roots[j]]
    return len(set(roots)), float(min(apart)) if apart else 0.0


__all__ = ["MAX_HOLE", "MERGE_TOLERANCE", "MeshRepair", "SLIVER_AREA", "TOUCH_GAP", "repair_mesh"]
