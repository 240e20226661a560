"""Pickling of frozen results that hold read-only mappings (``types.MappingProxyType``).

The standard pickler refuses a ``MappingProxyType``, and so do the transports built on
it: a ``ProcessPoolExecutor``'s queues (``gearbox run --jobs N``, a sweep sent to a
pool), Dask's executor, a user's ``pickle.dumps``. Classes whose fields hold such
mappings inherit :class:`PicklesReadOnly`: their state is pickled with every read-only
mapping in it (at any depth of dicts, lists and tuples) replaced by a stand-in that
unpickles as a read-only mapping again, and each read-only numpy array by one that
unpickles read-only again (a plain pickle gives it back writeable), so the unpickled
object equals the original field by field, what was read-only still read-only.
"""

from __future__ import annotations

import copyreg
import io
import pickle
from types import MappingProxyType
from typing import Any

import numpy as np

__all__ = ["PicklesReadOnly", "dumps", "picklable"]


def _read_only(items: dict) -> MappingProxyType:
    return MappingProxyType(items)


class _ReadOnly:
    """Stand-in for a read-only mapping in a pickle: unpickles as
    ``MappingProxyType(items)``."""

    __slots__ = ("items",)

    def __init__(self, items: dict):
        self.items = items

    def __reduce__(self):
        return (_read_only, (self.items,))


def _read_only_array(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


class _ReadOnlyArray:
    """Stand-in for a read-only array in a pickle: unpickles as the array, read-only."""

    __slots__ = ("array",)

    def __init__(self, array: np.ndarray):
        self.array = array

    def __reduce__(self):
        return (_read_only_array, (self.array,))


def picklable(x: Any) -> Any:
    """``x`` with each ``MappingProxyType`` and each read-only numpy array in it
    (itself, or inside plain dicts, lists and tuples, at any depth) replaced by a
    stand-in that unpickles as one; other values as they are (objects inside take
    care of their own state)."""
    if isinstance(x, np.ndarray):
        return x if x.flags.writeable else _ReadOnlyArray(x)
    if isinstance(x, MappingProxyType):
        return _ReadOnly({k: picklable(v) for k, v in x.items()})
    if type(x) is dict:
        return {k: picklable(v) for k, v in x.items()}
    if type(x) in (list, tuple):
        return type(x)(picklable(v) for v in x)
    return x


class PicklesReadOnly:
    """Mixin for (frozen) dataclasses with read-only mappings among their fields: the
    pickled state is the instance's ``__dict__`` through :func:`picklable`, restored
    as it is on unpickling (no ``__post_init__`` runs again)."""

    __slots__ = ()

    def __getstate__(self) -> dict[str, Any]:
        return {k: picklable(v) for k, v in self.__dict__.items()}

    def __copy__(self):
        # copy.copy takes the state as it is (no unpickling of the stand-ins)
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        return new


def dumps(obj: Any) -> bytes:
    """``pickle.dumps(obj)`` (highest protocol) that also takes a read-only mapping
    anywhere in ``obj``, inside objects that do not inherit :class:`PicklesReadOnly`
    too; it unpickles as a read-only mapping again. The cache's entries and the output
    worker's jobs are pickled so."""
    buf = io.BytesIO()
    pickler = pickle.Pickler(buf, protocol=pickle.HIGHEST_PROTOCOL)
    pickler.dispatch_table = copyreg.dispatch_table.copy()
    pickler.dispatch_table[MappingProxyType] = lambda m: (_read_only, (dict(m),))
    pickler.dump(obj)
    return buf.getvalue()
