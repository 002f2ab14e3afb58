"""The plain-C reference of the gridworld learners (``reference_gridworld.c``), built with the
system C compiler (``cc -O2``) into a temporary shared library and called through ctypes with the
compiled kernels' own arguments, so that both are timed in one process on the same work.

``load()`` returns None, after a one-line message, where there is no C compiler.
"""

import ctypes
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

SOURCE = Path(__file__).with_name("reference_gridworld.c")
LEARNERS = ("independent", "joint_state", "mmdp", "two_observe")


class _World(ctypes.Structure):
    _fields_ = [("next_cell", ctypes.c_void_p), ("is_goal", ctypes.c_void_p), ("starts", ctypes.c_void_p),
                ("bounce", ctypes.c_int64), ("n_cells", ctypes.c_int64), ("n_cols", ctypes.c_int64)]


def _pointer(array, dtype):
    """The address of ``array``'s data, which must already be C-contiguous of ``dtype`` (the C
    side writes into it)."""
    if array.dtype != dtype or not array.flags.c_contiguous:
        raise ValueError(f"the C reference needs a C-contiguous {np.dtype(dtype).name} array, got "
                         f"{array.dtype} {'contiguous' if array.flags.c_contiguous else 'strided'}")
    return array.ctypes.data_as(ctypes.c_void_p)


class Reference:
    """The C learners, each with the signature of its compiled kernel's ``run`` (two agents;
    2observe with the default need, ``in_range``, and delta in cells)."""

    def __init__(self, library: ctypes.CDLL):
        self._lib = library
        self._keep = []  # arrays the current World points into

    def _world(self, world):
        arrays = (np.ascontiguousarray(world.next_cell, np.int64), np.ascontiguousarray(world.is_goal, np.uint8),
                  np.ascontiguousarray(world.starts, np.int64))
        if arrays[2].shape != (2,):
            raise ValueError(f"the C reference is written for two agents, got {arrays[2].shape[0]}")
        self._keep = arrays
        return _World(*(a.ctypes.data for a in arrays), world.bounce, arrays[0].shape[0], world.n_cols)

    def _q_learner(self, name, world, learning, schedule, q, log, state):
        c_world = self._world(world)
        edges = np.ascontiguousarray(schedule.edges, np.int64)
        getattr(self._lib, "run_" + name)(
            ctypes.byref(c_world), ctypes.c_double(learning.q_learning_rate), ctypes.c_double(learning.discount),
            ctypes.c_double(learning.exploit_prob), ctypes.c_int64(schedule.episodes), _pointer(edges, np.int64),
            ctypes.c_int64(schedule.max_steps), _pointer(q, np.float64), _pointer(log, np.float64),
            _pointer(state, np.uint64))

    def independent(self, *args):
        self._q_learner("independent", *args)

    def joint_state(self, *args):
        self._q_learner("joint_state", *args)

    def mmdp(self, *args):
        self._q_learner("mmdp", *args)

    def two_observe(self, world, learning, automata, schedule, q, u, need_counts, log, state):
        a = automata
        if (a.gla_bounding, a.gla_need, a.gla_delta_scale, a.rule_distance) != (0, 0, 1.0, -1):
            raise ValueError("the C reference of 2observe has clip bounding, need in_range, delta in "
                             "cells and learning GLAs only")
        c_world = self._world(world)
        edges = np.ascontiguousarray(schedule.edges, np.int64)
        table = np.ascontiguousarray(a.gla_feedback, np.float64)
        double = ctypes.c_double
        self._lib.run_two_observe(
            ctypes.byref(c_world), double(learning.q_learning_rate), double(learning.discount),
            double(learning.exploit_prob), double(a.gla_learning_rate), double(a.gla_temperature), double(a.gla_K),
            double(a.gla_L), double(a.gla_init_range), _pointer(table, np.float64),
            double(a.coordination_penalty_per_cell), ctypes.c_int64(schedule.episodes), _pointer(edges, np.int64),
            ctypes.c_int64(schedule.max_steps), _pointer(q, np.float64), _pointer(u, np.float64),
            _pointer(need_counts, np.float64), _pointer(log, np.float64), _pointer(state, np.uint64))

    def run(self, name):
        """The C counterpart of ``glamas.learners.<name>.run``."""
        return getattr(self, name)


def load(build_dir=None):
    """Compile the reference with ``cc -O2`` and load it; None (and a message) without a compiler."""
    cc = shutil.which("cc")
    if cc is None:
        print("no C compiler (cc) found: the plain-C reference is skipped")
        return None
    build_dir = Path(build_dir or tempfile.mkdtemp(prefix="glamas-c-reference-"))
    library = build_dir / "reference_gridworld.so"
    subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", str(library), str(SOURCE), "-lm"], check=True)
    return Reference(ctypes.CDLL(str(library)))
