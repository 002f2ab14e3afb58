"""The plain-C reference of the gridworld learners (``reference_gridworld.c``), built with the
system C compiler (``cc -O2``) into a temporary shared library and called through ctypes on a
:class:`benchmarks.kernels.Workload`, so that it and the compiled kernel are timed in one process
on the same work.

``load()`` returns None, after a one-line message, where there is no C compiler.
"""

import ctypes
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks import kernels
from glamas.gridworld import BOUNCE_MODES
from glamas.learners import two_observe

SOURCE = Path(__file__).with_name("reference_gridworld.c")
LEARNERS = ("independent", "joint_state", "mmdp", "two_observe")
TWO_OBSERVE_SETTINGS = {"gla_bounding": "clip", "gla_need": "in_range", "gla_delta_scale": "cells",
                        "rule_distance": None}
"""The settings the C reference of 2observe is written for."""


class _World(ctypes.Structure):
    _fields_ = [("next_cell", ctypes.c_void_p), ("goal_of", ctypes.c_void_p), ("starts", ctypes.c_void_p),
                ("bounce", ctypes.c_int64), ("n_cells", ctypes.c_int64), ("n_cols", ctypes.c_int64),
                ("goal", ctypes.c_double), ("move", ctypes.c_double), ("bump", ctypes.c_double),
                ("collision", ctypes.c_double), ("collision_replaces_move", ctypes.c_int64)]


def _pointer(array, dtype):
    """The address of ``array``'s data, which must already be C-contiguous of ``dtype`` (the C
    side writes into it)."""
    if array.dtype != dtype or not array.flags.c_contiguous:
        raise ValueError(f"the C reference needs a C-contiguous {np.dtype(dtype).name} array, got "
                         f"{array.dtype} {'contiguous' if array.flags.c_contiguous else 'strided'}")
    return array.ctypes.data_as(ctypes.c_void_p)


class Reference:
    """The C learners: :meth:`run` is :func:`benchmarks.kernels.run_compiled` for one run (two
    agents; 2observe with the settings of TWO_OBSERVE_SETTINGS)."""

    def __init__(self, library: ctypes.CDLL):
        self._lib = library

    def run(self, workload: kernels.Workload, seed: int = 0) -> kernels.Outputs:
        """One run of the workload in C on the stream of run 0 of ``seed``; ``seconds`` is this
        thread's CPU time in the C call."""
        if workload.learner not in LEARNERS:
            raise ValueError(f"the C reference has the learners {LEARNERS}, not {workload.learner!r}")
        g, (q_settings, own) = workload.gridmap(), workload.setup()
        if g.n_agents != 2:
            raise ValueError(f"the C reference is written for two agents, got {g.n_agents}")
        arrays = kernels.new_outputs(workload, 1)
        world_arrays = (np.ascontiguousarray(g.next_cell, np.int64), np.ascontiguousarray(g.goal_table(), np.uint8),
                        np.ascontiguousarray(g.starts, np.int64))
        world = _World(*(a.ctypes.data for a in world_arrays), BOUNCE_MODES[workload.bounce], g.n_cells, g.n_cols,
                       *workload.rewards.kernel_bundle())
        double, state = ctypes.c_double, kernels.run_state(seed)
        common = (ctypes.byref(world), double(q_settings.q_learning_rate), double(q_settings.discount),
                  double(q_settings.exploit_prob))
        schedule = (ctypes.c_int64(workload.episodes), _pointer(workload.schedule().edges, np.int64),
                    ctypes.c_int64(workload.max_steps))
        q, log = _pointer(arrays["q"][0], np.float64), _pointer(arrays["log"][0], np.float64)
        start = time.thread_time()
        if workload.learner == "two_observe":
            self._lib.run_two_observe(*common, *self._automata(own, g), *schedule, q,
                                      _pointer(arrays["u"][0], np.float64), _pointer(arrays["u_initial"][0], np.float64),
                                      _pointer(arrays["need_counts"][0], np.float64),
                                      log, _pointer(state, np.uint64))
        else:
            getattr(self._lib, "run_" + workload.learner)(*common, *schedule, q, log, _pointer(state, np.uint64))
        return kernels.Outputs(arrays, time.thread_time() - start, workload.block)

    @staticmethod
    def _automata(c, gridmap) -> tuple:
        """2observe's GLA settings (glamas.learners.two_observe.GLASettings) on ``gridmap`` as the
        C function takes them."""
        wrong = {name: getattr(c, name) for name, value in TWO_OBSERVE_SETTINGS.items() if getattr(c, name) != value}
        if wrong:
            raise ValueError(f"the C reference of 2observe is written for {TWO_OBSERVE_SETTINGS}, got {wrong}")
        table = np.ascontiguousarray(c.gla_feedback, np.float64)
        double = ctypes.c_double
        return (double(c.gla_learning_rate), double(c.gla_temperature), double(c.gla_K), double(two_observe.box(c, gridmap)),
                double(c.gla_init_range), table.ctypes.data_as(ctypes.c_void_p), double(c.coordination_penalty_per_cell))


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
