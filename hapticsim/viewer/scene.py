"""A run drawn in a viser scene, and moved from state to state.

Layers (scene nodes under one name each, toggled together): ``/truth`` (the true solid, blue,
half transparent; a free object where it was at the state's last touch, SPEC §12),
``/contacts`` (one point cloud and one set of normals per touch, coloured by finger as in
``report.png``), ``/estimate`` (the estimate after the touch: one superquadric in
orange, a union's parts each in its colour), ``/hand`` (MuJoCo's geoms as meshes) and
``/taxels`` (the pressure image of the last contact's pad, beside the object, and below it
its taxels' states: stick blue, slip orange, SPEC §11). A label above
the object names the state: touch, contacts, the estimate's method and epsilon.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from hapticsim.viewer.run import RunData, State

#: Layer names, in the order of the viewer's toggles.
LAYERS: tuple[str, ...] = ("truth", "contacts", "normals", "estimate", "hand", "taxels")
#: Colours (RGB 0-255): truth, estimate parts; fingers follow matplotlib's tab colours as the
#: report does (hapticsim.exploration.report.FINGER_COLORS).
TRUTH_RGB: tuple[int, int, int] = (31, 119, 180)
PART_RGB: tuple[tuple[int, int, int], ...] = (
    (255, 127, 14), (255, 215, 0), (227, 119, 194), (23, 190, 207), (188, 189, 34),
)  # fmt: skip
FINGER_RGB: tuple[tuple[int, int, int], ...] = (
    (44, 160, 44), (214, 39, 40), (148, 103, 189), (140, 86, 75), (188, 189, 34), (127, 127, 127),
)  # fmt: skip
#: Surface mesh resolution (longitudes) of superquadrics.
RESOLUTION: int = 32


def finger_rgb(finger: int) -> tuple[int, int, int]:
    """The colour of finger `finger`'s contacts."""
    return FINGER_RGB[int(finger) % len(FINGER_RGB)]


def _pressure_rgb(image: np.ndarray) -> np.ndarray:
    """A pressure image (rows, cols) as an (rows, cols, 3) uint8 picture (viridis, own scale)."""
    from matplotlib import colormaps

    img = np.asarray(image, float)
    top = float(img.max()) if img.size and img.max() > 0 else 1.0
    rgb = colormaps["viridis"](np.clip(img / top, 0.0, 1.0))[..., :3]
    return (rgb * 255).astype(np.uint8)


#: Colours of the taxel states (free, stick, slip; SPEC §11).
STATE_RGB: np.ndarray = np.array([[40, 40, 48], [60, 130, 220], [240, 140, 40]], np.uint8)


def _state_rgb(state: np.ndarray) -> np.ndarray:
    """Taxel states (rows, cols) as an (rows, cols, 3) uint8 picture (:data:`STATE_RGB`)."""
    return STATE_RGB[np.clip(np.asarray(state, int), 0, len(STATE_RGB) - 1)]


class RunScene:
    """A run's layers in a viser scene (module docstring).

    Args:
        scene: a viser ``SceneApi`` (``server.scene``).
        run: the run.
        states: its replay (:func:`~hapticsim.viewer.run.replay_states`).
    """

    def __init__(self, scene: Any, run: RunData, states: list[State]) -> None:
        self.scene = scene
        self.run = run
        self.states = states
        self.state = -1
        self.visible = {name: True for name in LAYERS}
        self._touch_nodes: list[tuple[Any, Any]] = []
        self._estimate_nodes: list[Any] = []
        self._estimate_of: object | None = None
        self._hand_nodes: list[Any] = []
        self._taxel_node: Any = None
        self._state_node: Any = None
        self._taxel_shown = -1
        self._shown: dict[int, bool] = {}  # node id -> visibility sent (send changes only)
        self._truth_moved = False
        truth = run.truth
        lo, hi = truth.bounds
        self.center = (lo + hi) / 2.0
        self.extent = float(np.max(hi - lo))
        scene.set_up_direction("+z")
        self._truth_nodes = [
            scene.add_mesh_simple(f"/truth/part{k}", *_mesh(part), color=TRUTH_RGB,
                                  opacity=0.35, side="double", cast_shadow=False)
            for k, part in enumerate(truth.components)
        ]  # fmt: skip
        self._add_touches()
        self._add_hand()
        self._label = scene.add_label("/status", "", position=self.center + [0, 0, self.extent],
                                      anchor="bottom-center")  # fmt: skip

    # ------------------------------------------------------------------ building
    def _add_touches(self) -> None:
        run = self.run
        arrow = 0.12 * self.extent
        start = 0
        for state in self.states:
            end = state.contacts
            if end <= start:
                self._touch_nodes.append((None, None))
                continue
            i = len(self._touch_nodes)
            pts = run.points[start:end]
            colors = np.array([finger_rgb(f) for f in run.finger[start:end]], np.uint8)
            cloud = self.scene.add_point_cloud(
                f"/contacts/touch{i:04d}", pts, colors, point_size=0.06 * self.extent,
                point_shape="circle", point_shading="flat", precision="float32", visible=False,
            )  # fmt: skip
            seg = np.stack([pts, pts + arrow * run.normals[start:end]], axis=1)
            lines = self.scene.add_line_segments(
                f"/normals/touch{i:04d}", seg, np.repeat(colors[:, None], 2, axis=1),
                thickness=0.006 * self.extent, visible=False,
            )  # fmt: skip
            self._touch_nodes.append((cloud, lines))
            start = end

    def _add_hand(self) -> None:
        hand = self.run.hand
        if hand is None:
            return
        vs, fs = hand["vertex_start"], hand["face_start"]
        for g in range(len(vs) - 1):
            v = hand["vertices"][vs[g]:vs[g + 1]]
            f = hand["faces"][fs[g]:fs[g + 1]]
            if len(f) == 0:
                self._hand_nodes.append(None)
                continue
            rgb = tuple(int(c * 255) for c in hand["rgba"][g][:3])
            self._hand_nodes.append(self.scene.add_mesh_simple(
                f"/hand/geom{g:03d}", v, f, color=rgb, cast_shadow=False,
            ))  # fmt: skip

    # ------------------------------------------------------------------ moving
    def show(self, k: int) -> None:
        """Draw state `k` (0 .. len(states) - 1)."""
        k = int(np.clip(k, 0, len(self.states) - 1))
        state = self.states[k]
        for i, (cloud, lines) in enumerate(self._touch_nodes):
            if cloud is None:
                continue
            seen = i <= k
            self._set_visible(cloud, seen and self.visible["contacts"])
            self._set_visible(lines, seen and self.visible["normals"])
        if state.hand_position is not None:
            for g, node in enumerate(self._hand_nodes):
                if node is not None:
                    node.position = state.hand_position[g]
                    node.wxyz = state.hand_wxyz[g]
                    self._set_visible(node, self.visible["hand"])
        moved = self._move_truth(state)
        self._show_estimate(state)
        self._show_taxels(state)
        eps = "" if state.epsilon is None else f", epsilon {state.epsilon:.3f}"
        fit = "no estimate yet (13 contacts needed)" if state.estimate is None else (
            f"{state.method} estimate{eps}"
        )  # fmt: skip
        self._label.text = (
            f"touch {k} of {len(self.states) - 1}: {state.contacts} contacts, {fit}{moved}"
        )
        self.state = k

    def _move_truth(self, state: State) -> str:
        """Carry a free object's truth to where it was at the state's last contact; the
        label's words for how far that is from rest ('' for a fixed object)."""
        pose = state.object_pose
        if pose is None:
            if self._truth_moved:  # back to a state before the first contact: at rest
                for node in self._truth_nodes:
                    node.position, node.wxyz = (0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0)
                self._truth_moved = False
            return ""
        for node in self._truth_nodes:
            node.position = pose[:3]
            node.wxyz = pose[3:]
        self._truth_moved = True
        from hapticsim.fitting.track import IDENTITY_POSE, pose_drift

        rest = pose_drift(pose, IDENTITY_POSE, self.center)
        return (f"; the object moved {1000 * rest['position_m']:.1f} mm, "
                f"{rest['angle_deg']:.1f} deg")  # fmt: skip

    def _show_estimate(self, state: State) -> None:
        if state.estimate is not self._estimate_of:
            for node in self._estimate_nodes:
                node.remove()
            self._estimate_nodes = []
            if state.estimate is not None:
                for j, part in enumerate(state.estimate.components):
                    v, f = _mesh(part)
                    self._estimate_nodes.append(self.scene.add_mesh_simple(
                        f"/estimate/part{j}", v, f, color=PART_RGB[j % len(PART_RGB)],
                        opacity=0.6, side="double", cast_shadow=False,
                        visible=self.visible["estimate"],
                    ))  # fmt: skip
            self._estimate_of = state.estimate
        for node in self._estimate_nodes:
            self._set_visible(node, self.visible["estimate"])

    def _set_visible(self, node: Any, visible: bool) -> None:
        if self._shown.get(id(node)) != visible:
            node.visible = visible
            self._shown[id(node)] = visible

    def _show_taxels(self, state: State) -> None:
        taxels = self.run.taxels
        if taxels is None or state.contacts == 0:
            for node in (self._taxel_node, self._state_node):
                if node is not None:
                    node.visible = False
            return
        last = state.contacts - 1
        if last != self._taxel_shown:
            size = 0.6 * self.extent
            self._taxel_node = self.scene.add_image(
                "/taxels/pad", _pressure_rgb(taxels[last]), size, size, format="png",
                position=self.center + [1.1 * self.extent, 0.0, 0.0],
                wxyz=(0.5, 0.5, 0.5, 0.5), cast_shadow=False,
            )  # fmt: skip
            if self.run.taxel_state is not None:  # stick and slip, below the pressure
                self._state_node = self.scene.add_image(
                    "/taxels/state", _state_rgb(self.run.taxel_state[last]), size, size,
                    format="png", position=self.center + [1.1 * self.extent, 0.0,
                                                          -0.7 * self.extent],
                    wxyz=(0.5, 0.5, 0.5, 0.5), cast_shadow=False,
                )  # fmt: skip
            self._taxel_shown = last
        self._taxel_node.visible = self.visible["taxels"]
        if self._state_node is not None:
            self._state_node.visible = self.visible["taxels"]

    def set_layer(self, name: str, visible: bool) -> None:
        """Show or hide layer `name` (:data:`LAYERS`) and redraw the current state."""
        self.visible[name] = bool(visible)
        for node in self._truth_nodes:
            self._set_visible(node, self.visible["truth"])
        if self.state >= 0:
            self.show(self.state)

    def layers(self) -> tuple[str, ...]:
        """The layers this run has (:data:`LAYERS` less those whose file is missing)."""
        absent = {"hand"} if self.run.hand is None else set()
        if self.run.taxels is None:
            absent.add("taxels")
        return tuple(n for n in LAYERS if n not in absent)

    def aim(self, camera: Any) -> None:
        """Point an (initial) camera at the object from the front, above, the hand in view."""
        camera.look_at = tuple(self.center)
        camera.position = tuple(self.center + np.array([1.5, -2.1, 1.4]) * self.extent)
        camera.near = 0.01 * self.extent


def _mesh(solid: Any) -> tuple[np.ndarray, np.ndarray]:
    v, f = solid.surface_mesh(RESOLUTION)
    return np.asarray(v, np.float32), np.asarray(f, np.int32)


__all__ = ["LAYERS", "RunScene", "finger_rgb"]
