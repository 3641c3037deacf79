"""The contacts of a world's last step as numpy arrays (copies: the engine rebuilds its
contact list at every step)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Contacts:
    """One row per contact point of the last step, open ones (zero impulse) included.

    a, b:     the bodies; b < 0 names container wall -1 - b (docs/output-format.md)
    point:    (n, 3) contact point, world frame
    normal:   (n, 3) unit normal from B towards A
    gap:      (n,) signed gap along the normal at detection (negative: overlap)
    mu:       (n,) friction coefficient
    impulse:  (n, 3) the solver's impulse on A in the contact frame (normal, t1, t2)
    force:    (n, 3) the impulse on A over the step, world frame: impulse / h
    """

    a: np.ndarray
    b: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    mu: np.ndarray
    impulse: np.ndarray
    force: np.ndarray

    def __len__(self) -> int:
        return len(self.a)

    @property
    def wall(self) -> np.ndarray:
        """Wall index of each contact, -1 for a contact between two bodies."""
        return np.where(self.b < 0, -1 - self.b, -1)

    @property
    def active(self) -> np.ndarray:
        """Contacts that carry a positive normal impulse (what timeseries.csv counts)."""
        return self.impulse[:, 0] > 0
