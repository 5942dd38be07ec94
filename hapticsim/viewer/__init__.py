"""A 3-D viewer of explore runs in the browser (extra ``viewer``: viser).

``hapticsim view RUN_DIR`` serves the run (:func:`serve`); ``--export FILE.html`` writes one
self-contained page that replays it offline (:func:`export_html`). :mod:`.run` reads a run
directory and cuts it into one state per touch; :mod:`.scene` draws a state in viser's scene.
"""

from hapticsim.viewer.run import RunData, State, load_run, missing_files, replay_states
from hapticsim.viewer.serve import export_html, serve

__all__ = ["RunData", "State", "export_html", "load_run", "missing_files", "replay_states",
           "serve"]  # fmt: skip
