"""The answers of Structure.intersect() and Field.intersect(): named tuples of NumPy arrays, one entry per ray."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

__all__ = ["FieldHits", "Hits"]


def _summary(t: Any) -> str:
    """'N rays, H hits' for an array of t, or the one ray's t."""
    if np.ndim(t) == 0:
        return "a miss" if not np.isfinite(t) else f"t={float(t):.7g}"
    hits = int(np.count_nonzero(np.isfinite(t)))
    return f"{np.size(t)} rays, {hits} hits"


class Hits(NamedTuple):
    """Closest hits, one entry per ray (scalars for one ray given as (3,) vectors).

    A miss has t = inf, prim = instance = visfield.INVALID_ID, u = v = 0 and a zero normal; a hit
    through a field (ObjectField) has prim = INVALID_ID. The normal is the geometric one, not normalised.
    """

    t: Any
    """float32 (N,): the distance along the ray's direction (inf for a miss)."""
    prim: Any
    """uint32 (N,): the triangle's index in its object."""
    instance: Any
    """uint32 (N,): the object's (instance's) index in the scene."""
    u: Any
    """float32 (N,): the first barycentric coordinate."""
    v: Any
    """float32 (N,): the second barycentric coordinate."""
    normal: Any
    """float32 (N, 3): the geometric normal of the triangle hit."""

    @property
    def hit(self) -> Any:
        """bool (N,): whether each ray hit (t is finite)."""
        return np.isfinite(self.t)

    def __repr__(self) -> str:
        if np.ndim(self.t) == 0 and np.isfinite(self.t):
            return (f"Hits(t={float(self.t):.7g}, prim={int(self.prim)}, instance={int(self.instance)}, "
                    f"u={float(self.u):.7g}, v={float(self.v):.7g}, "
                    f"normal=[{', '.join('%.7g' % x for x in np.asarray(self.normal).tolist())}])")
        return f"Hits({_summary(self.t)}; fields t, prim, instance, u, v, normal)"


class FieldHits(NamedTuple):
    """Approximate closest hits through a field, one entry per ray (scalars for one ray)."""

    t: Any
    """float32 (N,): the distance along the ray's direction (inf for a miss)."""
    normal: Any
    """float32 (N, 3): the unit normal where the field stores normals, zero otherwise."""

    @property
    def hit(self) -> Any:
        """bool (N,): whether each ray hit (t is finite)."""
        return np.isfinite(self.t)

    def __repr__(self) -> str:
        return f"FieldHits({_summary(self.t)}; fields t, normal)"
