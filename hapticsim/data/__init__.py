"""Contact data: synthetic exploration patterns of the paper (III-A) and file I/O (SPEC §5-6).

- :mod:`~hapticsim.data.patterns`: :class:`Stripe` and :class:`Patch` on a superquadric (eq. 6).
- :mod:`~hapticsim.data.noise`: relative Gaussian noise on points and normals (SPEC §5).
- :mod:`~hapticsim.data.bodies`: the paper's four bodies, :func:`get_body`, :func:`resolve_body`.
- :mod:`~hapticsim.data.synthetic`: :func:`paper_dataset`, the paper's exploration data sets.
- :mod:`~hapticsim.data.io`: :class:`Contacts` and contact/JSON files.
- :mod:`~hapticsim.data.objects`: objects from anywhere (``ObjectSpec``: body names, superquadric
  files, random shapes, mesh files); :mod:`~hapticsim.data.example_meshes`.
- :mod:`~hapticsim.data.distributions`: which object an episode gets (``ObjectDistribution``,
  ``ObjectSet``).
"""

from hapticsim.data.bodies import BODY_NAMES, get_body, resolve_body
from hapticsim.data.io import Contacts, read_contacts, write_contacts
from hapticsim.data.noise import add_noise
from hapticsim.data.patterns import Patch, Stripe, sample_patterns
from hapticsim.data.synthetic import paper_dataset, paper_patterns

__all__ = [
    "BODY_NAMES",
    "Contacts",
    "Patch",
    "Stripe",
    "add_noise",
    "get_body",
    "paper_dataset",
    "paper_patterns",
    "read_contacts",
    "resolve_body",
    "sample_patterns",
    "write_contacts",
]
