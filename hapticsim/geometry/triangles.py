"""Geometry on arrays of triangles: closest points, area-uniform samples, refinement.

numpy only; used by :class:`~hapticsim.geometry.mesh_solid.MeshSolid` and by the metrics.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: (point, triangle) pairs evaluated at once by :func:`nearest_of_pairs` (memory ~ 500 B each).
PAIR_BATCH: int = 2_000_000


def closest_point_on_triangles(triangles: Array, points: Array) -> Array:
    """Closest point of each triangle to its point (Ericson, Real-Time Collision Detection 5.1.5).

    Args:
        triangles: (n, 3, 3) float, vertices a, b, c of n triangles [m].
        points: (n, 3) float, one query point per triangle [m].

    Returns:
        (n, 3) float closest points [m]. Degenerate (zero-area) triangles mostly fall into an
        edge or vertex region; where none holds the result is NaN, which callers must skip.
    """
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, ac = b - a, c - a
    ap, bp, cp = points - a, points - b, points - c
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = 1.0 / (va + vb + vc)
        out = a + ab * (vb * denom)[:, None] + ac * (vc * denom)[:, None]  # inside the face
        # Voronoi regions of edges and vertices, applied from the last test to the first so
        # that the first one that holds wins, as in Ericson's sequence of early returns.
        w_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        regions = [
            ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), b + (c - b) * w_bc[:, None]),
            ((vb <= 0) & (d2 >= 0) & (d6 <= 0), a + ac * (d2 / (d2 - d6))[:, None]),
            ((d6 >= 0) & (d5 <= d6), c),
            ((vc <= 0) & (d1 >= 0) & (d3 <= 0), a + ab * (d1 / (d1 - d3))[:, None]),
            ((d3 >= 0) & (d4 <= d3), b),
            ((d1 <= 0) & (d2 <= 0), a),
        ]
        for mask, value in regions:
            out = np.where(mask[:, None], value, out)
    return out


def sample_triangles(
    triangles: Array, areas: Array, count: int, rng: np.random.Generator
) -> tuple[Array, NDArray[np.int64]]:
    """Points uniform by area on a set of triangles.

    Args:
        triangles: (m, 3, 3) float, triangle vertices [m].
        areas: (m,) float, their areas [m^2].
        count: number of points.
        rng: the generator (draws the faces, then the barycentric coordinates).

    Returns:
        points (count, 3) [m] and the index (count,) of the triangle of each.
    """
    cumulative = np.cumsum(areas)
    face = np.searchsorted(cumulative, rng.uniform(0.0, cumulative[-1], count), side="right")
    face = np.minimum(face, len(cumulative) - 1)
    r = rng.random((count, 2))
    flip = r.sum(axis=1) > 1.0
    r[flip] = 1.0 - r[flip]
    t = triangles[face]
    points = t[:, 0] + r[:, :1] * (t[:, 1] - t[:, 0]) + r[:, 1:] * (t[:, 2] - t[:, 0])
    return points, face


def split_long_edges(triangles: Array, max_edge: float) -> tuple[Array, NDArray[np.int64]]:
    """Triangles halved at the midpoint of their longest edge until every edge is at most
    `max_edge` [m].

    Args:
        triangles: (m, 3, 3) float [m].
        max_edge: longest edge kept [m], > 0.

    Returns:
        the pieces (k, 3, 3) [m] (their union is the input) and the index (k,) of the input
        triangle of each.
    """
    tri = np.asarray(triangles, dtype=np.float64)
    parent = np.arange(len(tri))
    done_tri, done_parent = [], []
    while len(tri):
        edges = np.stack(
            [tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 1], tri[:, 0] - tri[:, 2]], axis=1
        )
        length = np.linalg.norm(edges, axis=2)
        long = length.max(axis=1) > max_edge
        done_tri.append(tri[~long])
        done_parent.append(parent[~long])
        tri, parent, length = tri[long], parent[long], length[long]
        k = np.argmax(length, axis=1)  # edge k runs from vertex k to vertex k + 1
        rows = np.arange(len(tri))
        a, b, c = tri[rows, k], tri[rows, (k + 1) % 3], tri[rows, (k + 2) % 3]
        mid = 0.5 * (a + b)
        tri = np.concatenate([np.stack([a, mid, c], 1), np.stack([mid, b, c], 1)])
        parent = np.concatenate([parent, parent])
    return np.concatenate(done_tri), np.concatenate(done_parent)


def nearest_of_pairs(
    triangles: Array,
    points: Array,
    point_index: NDArray[np.int64],
    triangle_index: NDArray[np.int64],
) -> tuple[Array, NDArray[np.int64]]:
    """Per point, the closest point on the nearest of its candidate triangles.

    Args:
        triangles: (m, 3, 3) float [m].
        points: (n, 3) float [m].
        point_index, triangle_index: (p,) int, the candidate pairs (every point at least once).

    Returns:
        closest (n, 3) [m] and the index (n,) of the triangle it lies on.
    """
    best_d = np.full(len(points), np.inf)
    best_q = np.zeros_like(points)
    best_t = np.zeros(len(points), dtype=np.int64)
    for start in range(0, len(point_index), PAIR_BATCH):
        pi = point_index[start : start + PAIR_BATCH]
        ti = triangle_index[start : start + PAIR_BATCH]
        cand = closest_point_on_triangles(triangles[ti], points[pi])
        d = np.linalg.norm(cand - points[pi], axis=1)
        d = np.where(np.isfinite(d), d, np.inf)
        order = np.lexsort((d, pi))  # per point, nearest first
        first = np.ones(len(order), dtype=bool)
        first[1:] = pi[order][1:] != pi[order][:-1]
        sel = order[first]
        rows = pi[sel]
        better = d[sel] < best_d[rows]
        rows, sel = rows[better], sel[better]
        best_d[rows] = d[sel]
        best_q[rows] = cand[sel]
        best_t[rows] = ti[sel]
    return best_q, best_t


#: Query points times triangles below which :class:`TriangleSearch` tests every pair.
BRUTE_PAIRS: int = 2_000_000
#: Nearest pieces first tested per point by :class:`TriangleSearch`.
FIRST_CANDIDATES: int = 16


def all_pairs_nearest(triangles: Array, points: Array) -> tuple[Array, NDArray[np.int64]]:
    """Per point, the closest point of the triangles and the triangle it lies on, testing every
    (point, triangle) pair in batches (exact)."""
    m = len(triangles)
    closest, face = np.zeros_like(points), np.zeros(len(points), dtype=np.int64)
    step = max(1, PAIR_BATCH // m)
    for start in range(0, len(points), step):
        chunk = points[start : start + step]
        pi = np.repeat(np.arange(len(chunk)), m)
        fi = np.tile(np.arange(m), len(chunk))
        s = slice(start, start + len(chunk))
        closest[s], face[s] = nearest_of_pairs(triangles, chunk, pi, fi)
    return closest, face


class TriangleSearch:
    """The closest point of a set of triangles to many points, fast and exact.

    The triangles are split into pieces with edges of at most `max_edge` (:func:`split_long_edges`)
    whose centroids go into a tree (scipy ``cKDTree``). Each point's k pieces with the nearest
    centroids are tested, k = 16, 64, 256, ..., until the nearest piece found is no farther than
    the k-th centroid less the pieces' largest reach from their centroids (no untested piece can
    be nearer). With ``exact=False`` the first 16 pieces are all that is tested: far points then
    may get a slightly farther point (measured on the example meshes for Chamfer samples up to
    3 cm off: mean distance within 1e-8 m of the exact one). Small exact problems test every pair
    (``exact=False`` never does: 16 pieces per point cost a small fraction of every pair once the
    points number thousands).

    Args:
        triangles: (m, 3, 3) float [m].
        max_edge: longest edge of a piece [m] (a sixteenth of the object's size is good).
    """

    def __init__(self, triangles: Array, max_edge: float) -> None:
        from scipy.spatial import cKDTree

        self.triangles = np.asarray(triangles, dtype=np.float64)
        self.pieces, self.face_of = split_long_edges(self.triangles, max_edge)
        centroid = self.pieces.mean(axis=1)
        self.reach = float(np.max(np.linalg.norm(self.pieces - centroid[:, None, :], axis=2)))
        self.tree = cKDTree(centroid)

    def nearest(self, points: Array, exact: bool = True) -> tuple[Array, NDArray[np.int64]]:
        """closest (n, 3) float [m] and the triangle (n,) int it lies on, per point (n, 3)."""
        p = np.asarray(points, dtype=np.float64)
        if exact and len(p) * len(self.triangles) <= BRUTE_PAIRS:
            return all_pairs_nearest(self.triangles, p)
        closest = np.zeros_like(p)
        face = np.zeros(len(p), dtype=np.int64)
        todo = np.arange(len(p))
        k = FIRST_CANDIDATES
        while len(todo):
            k = min(k, len(self.pieces))
            dist, idx = self.tree.query(p[todo], k=k)
            dist, idx = dist.reshape(len(todo), k), idx.reshape(len(todo), k)
            pi = np.repeat(np.arange(len(todo)), k)
            q, piece = nearest_of_pairs(self.pieces, p[todo], pi, idx.ravel())
            found = np.linalg.norm(q - p[todo], axis=1)
            done = (found <= dist[:, -1] - self.reach) | (k == len(self.pieces)) | (not exact)
            closest[todo[done]], face[todo[done]] = q[done], self.face_of[piece[done]]
            todo = todo[~done]
            k *= 4
        return closest, face


__all__ = [
    "BRUTE_PAIRS",
    "FIRST_CANDIDATES",
    "PAIR_BATCH",
    "TriangleSearch",
    "all_pairs_nearest",
    "closest_point_on_triangles",
    "nearest_of_pairs",
    "sample_triangles",
    "split_long_edges",
]
